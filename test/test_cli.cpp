/*
 * pcl_graph_denoise: graph-signal-processing point cloud denoising for PCL.
 * SPDX-License-Identifier: BSD-3-Clause
 *
 * The command-line tool (tools/pcl_graph_denoise), run as a program on clouds written
 * by the tests: every field but x, y, z survives bit for bit, outlier removal splits the
 * points between the output and the -removed file, parameters reach the filters, ASCII
 * and binary, PCD and PLY; and every kind of bad input gives a one-line error, a
 * non-zero exit code and no output file.
 */
#include <pcl_graph_denoise/graph_degree_outlier_removal.h>
#include <pcl_graph_denoise/graph_sequence_smoothing.h>
#include <pcl_graph_denoise/graph_tikhonov_smoothing.h>
#include <pcl_graph_denoise/graph_tv_smoothing.h>

#include "synthetic.h"
#include "test_clouds.h"

#include <gtest/gtest.h>

#include <pcl/PCLPointCloud2.h>
#include <pcl/common/io.h>
#include <pcl/console/print.h>
#include <pcl/io/pcd_io.h>
#include <pcl/io/ply_io.h>

#include <fcntl.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <limits>
#include <map>
#include <set>
#include <sstream>
#include <string>
#include <vector>

extern char **environ;

namespace {

namespace fs = std::filesystem;
using pcl::PCLPointCloud2;
using pcl::PCLPointField;

// --- Running the tool --------------------------------------------------------------------

struct ToolRun
{
  int code = -1;
  std::string out, err;
};

std::string
readFile (const fs::path &path)
{
  std::ifstream in (path, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf ();
  return s.str ();
}

/** A fresh folder for one test, named after it. Also quiets PCL's warnings in the
 *  test's own reading (one line per PLY property PCL does not handle). */
fs::path
testFolder ()
{
  pcl::console::setVerbosityLevel (pcl::console::L_ERROR);
  const auto *info = ::testing::UnitTest::GetInstance ()->current_test_info ();
  const fs::path dir = fs::path (PCL_GRAPH_DENOISE_CLI_WORK_DIR) /
                       (std::string (info->test_suite_name ()) + "." + info->name ());
  fs::remove_all (dir);
  fs::create_directories (dir);
  fs::create_directories (dir.string () + ".log");
  return dir;
}

/** Runs the tool in `dir` (file names relative to it) and collects its exit code,
 *  stdout and stderr. */
ToolRun
runTool (const fs::path &dir, const std::vector<std::string> &args)
{
  std::vector<std::string> words = {PCL_GRAPH_DENOISE_CLI};
  words.insert (words.end (), args.begin (), args.end ());
  std::vector<char *> argv;
  for (auto &w : words)
    argv.push_back (w.data ());
  argv.push_back (nullptr);
  const std::string out = dir.string () + ".log/stdout", err = dir.string () + ".log/stderr";
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init (&actions);
  posix_spawn_file_actions_addchdir_np (&actions, dir.c_str ());
  posix_spawn_file_actions_addopen (&actions, 1, out.c_str (), O_WRONLY | O_CREAT | O_TRUNC, 0644);
  posix_spawn_file_actions_addopen (&actions, 2, err.c_str (), O_WRONLY | O_CREAT | O_TRUNC, 0644);
  ToolRun run;
  pid_t pid;
  if (posix_spawn (&pid, argv[0], &actions, nullptr, argv.data (), environ) == 0)
  {
    int status = 0;
    waitpid (pid, &status, 0);
    run.code = WIFEXITED (status) ? WEXITSTATUS (status) : 128 + WTERMSIG (status);
  }
  posix_spawn_file_actions_destroy (&actions);
  run.out = readFile (out);
  run.err = readFile (err);
  return run;
}

std::string
describe (const std::vector<std::string> &args, const ToolRun &run)
{
  std::string text = "pcl_graph_denoise";
  for (const auto &a : args)
    text += " " + a;
  return text + "\nexit " + std::to_string (run.code) + "\nstderr:\n" + run.err;
}

// --- Clouds ------------------------------------------------------------------------------

/** A cloud with x, y, z of the given type and, around them, fields of many types whose
 *  values are derived from the index: rgb (packed, opaque), normals, intensity, a unique
 *  "id" (the original index, to match points after outlier removal), a 16-bit ring and a
 *  double time stamp. */
PCLPointCloud2
makeCloud (const pcl::PointCloud<pcl::PointXYZ> &xyz, std::uint8_t coordinate_type,
           std::uint32_t width, std::uint32_t height)
{
  PCLPointCloud2 cloud;
  const std::uint32_t coordinate_size = coordinate_type == PCLPointField::FLOAT64 ? 8 : 4;
  std::uint32_t offset = 0;
  const auto add = [&] (const std::string &name, std::uint8_t type, std::uint32_t size) {
    PCLPointField f;
    f.name = name;
    f.offset = offset;
    f.datatype = type;
    f.count = 1;
    cloud.fields.push_back (f);
    offset += size;
  };
  add ("x", coordinate_type, coordinate_size);
  add ("y", coordinate_type, coordinate_size);
  add ("z", coordinate_type, coordinate_size);
  add ("rgb", PCLPointField::FLOAT32, 4);
  add ("normal_x", PCLPointField::FLOAT32, 4);
  add ("normal_y", PCLPointField::FLOAT32, 4);
  add ("normal_z", PCLPointField::FLOAT32, 4);
  add ("intensity", PCLPointField::FLOAT32, 4);
  add ("id", PCLPointField::UINT32, 4);
  add ("ring", PCLPointField::UINT16, 2);
  add ("time", PCLPointField::FLOAT64, 8);
  cloud.point_step = offset;
  cloud.width = width;
  cloud.height = height;
  cloud.row_step = width * offset;
  cloud.data.resize (std::size_t (cloud.row_step) * height);
  cloud.is_dense = true;
  for (std::size_t i = 0; i < xyz.size (); ++i)
  {
    std::uint8_t *p = cloud.data.data () + i * offset;
    const auto put = [&] (std::size_t field, auto value) {
      std::memcpy (p + cloud.fields[field].offset, &value, sizeof (value));
    };
    const auto &q = xyz[i];
    if (coordinate_type == PCLPointField::FLOAT64)
    {
      // Doubles that are not floats: the tool must move them by a displacement.
      put (0, double (q.x) + 1e-12 * double (i % 7));
      put (1, double (q.y));
      put (2, double (q.z));
    }
    else
    {
      put (0, q.x);
      put (1, q.y);
      put (2, q.z);
    }
    cloud.is_dense = cloud.is_dense && std::isfinite (q.x);
    const std::uint32_t rgb =
        0xff000000u | static_cast<std::uint32_t> ((i * 2654435761u) & 0xffffff);
    float rgb_float;
    std::memcpy (&rgb_float, &rgb, 4);
    put (3, rgb_float);
    put (4, static_cast<float> (std::sin (0.1 * i)));
    put (5, static_cast<float> (std::cos (0.1 * i)));
    put (6, 0.25f + 1e-3f * static_cast<float> (i % 100));
    put (7, static_cast<float> (i % 1000) / 7.0f);
    put (8, static_cast<std::uint32_t> (i));
    put (9, static_cast<std::uint16_t> (i % 64));
    put (10, 1.7e9 + 1e-3 * double (i));
  }
  return cloud;
}

/** A noisy unit sphere (2000 points, noise 1%) with 5% uniform outliers, unorganised. */
PCLPointCloud2
sphereWithOutliers (std::uint8_t coordinate_type = PCLPointField::FLOAT32)
{
  auto xyz = pcl_graph_denoise::synthetic::noisySphere (2000, 1.0, 0.01, 7);
  pcl_graph_denoise::synthetic::addUniformOutliers (xyz, 0.05, 0.3, 8);
  return makeCloud (xyz, coordinate_type, static_cast<std::uint32_t> (xyz.size ()), 1);
}

/** An organised 50 x 40 noisy plane (z = noise) with every 37th point NaN. */
PCLPointCloud2
organisedPlane (std::uint8_t coordinate_type = PCLPointField::FLOAT32)
{
  const std::uint32_t width = 50, height = 40;
  auto xyz = pcl_graph_denoise::synthetic::noisyPlane (width * height, 0.01, 9);
  // Grid order (an organised scan), noise kept from the generated cloud.
  for (std::uint32_t r = 0; r < height; ++r)
    for (std::uint32_t c = 0; c < width; ++c)
    {
      auto &p = xyz[r * width + c];
      p.x = -1.0f + 2.0f * c / (width - 1);
      p.y = -1.0f + 2.0f * r / (height - 1);
      if ((r * width + c) % 37 == 5)
        p.x = p.y = p.z = std::numeric_limits<float>::quiet_NaN ();
    }
  return makeCloud (xyz, coordinate_type, width, height);
}

void
savePcd (const fs::path &path, const PCLPointCloud2 &cloud, bool binary = true)
{
  ASSERT_EQ (pcl::io::savePCDFile (path.string (), cloud, Eigen::Vector4f::Zero (),
                                   Eigen::Quaternionf::Identity (), binary),
             0);
}

void
savePly (const fs::path &path, const PCLPointCloud2 &cloud, bool binary = true)
{
  ASSERT_EQ (pcl::io::savePLYFile (path.string (), cloud, Eigen::Vector4f::Zero (),
                                   Eigen::Quaternionf::Identity (), binary),
             0);
}

PCLPointCloud2
load (const fs::path &path)
{
  PCLPointCloud2 cloud;
  const std::string ext = path.extension ().string ();
  const int rc = ext == ".ply" ? pcl::io::loadPLYFile (path.string (), cloud)
                               : pcl::io::loadPCDFile (path.string (), cloud);
  EXPECT_EQ (rc, 0) << path;
  return cloud;
}

std::size_t
size (const PCLPointCloud2 &cloud)
{
  return std::size_t (cloud.width) * cloud.height;
}

const PCLPointField *
field (const PCLPointCloud2 &cloud, const std::string &name)
{
  for (const auto &f : cloud.fields)
    if (f.name == name)
      return &f;
  return nullptr;
}

/** The bytes of a field of point i. */
std::string
bytes (const PCLPointCloud2 &cloud, std::size_t i, const PCLPointField &f)
{
  const std::size_t n = pcl::getFieldSize (f.datatype) * f.count;
  const auto *p = cloud.data.data () + (i / cloud.width) * cloud.row_step +
                  (i % cloud.width) * cloud.point_step + f.offset;
  return std::string (reinterpret_cast<const char *> (p), n);
}

double
coordinate (const PCLPointCloud2 &cloud, std::size_t i, const char *name)
{
  const PCLPointField &f = *field (cloud, name);
  const std::string b = bytes (cloud, i, f);
  if (f.datatype == PCLPointField::FLOAT64)
  {
    double v;
    std::memcpy (&v, b.data (), 8);
    return v;
  }
  float v;
  std::memcpy (&v, b.data (), 4);
  return v;
}

std::uint32_t
id (const PCLPointCloud2 &cloud, std::size_t i)
{
  std::uint32_t v;
  std::memcpy (&v, bytes (cloud, i, *field (cloud, "id")).data (), 4);
  return v;
}

bool
finite (const PCLPointCloud2 &cloud, std::size_t i)
{
  return std::isfinite (coordinate (cloud, i, "x")) && std::isfinite (coordinate (cloud, i, "y")) &&
         std::isfinite (coordinate (cloud, i, "z"));
}

bool
isCoordinate (const std::string &name)
{
  return name == "x" || name == "y" || name == "z";
}

/** How two clouds are compared: from and to the same binary format, every byte and
 *  type. Between PCD and PLY, rgb goes through PLY's red, green and blue properties
 *  (PCL's PLY writer drops the alpha byte of an rgb field, and its reader may type it
 *  differently), and PCL's ASCII PCD writer declares a float rgb as TYPE U (same bits):
 *  there only rgb's colour is compared. */
enum class Formats
{
  SAME,
  CROSSED
};

/** Colour bytes of an rgb field value. */
std::uint32_t
colour (const std::string &rgb_bytes)
{
  std::uint32_t v;
  std::memcpy (&v, rgb_bytes.data (), 4);
  return v & 0xffffffu;
}

/** Checks that `output` has the fields of `input` (same names, types, counts) and that
 *  each of its points holds, in every field but x, y, z, the bytes of the input point
 *  with the same id. Returns the input index of each output point. */
std::vector<std::size_t>
expectFieldsKept (const PCLPointCloud2 &input, const PCLPointCloud2 &output,
                  Formats formats = Formats::SAME)
{
  const bool crossed = formats == Formats::CROSSED;
  std::vector<std::size_t> origin;
  EXPECT_EQ (pcl::getFieldsList (output), pcl::getFieldsList (input));
  for (const auto &f : input.fields)
  {
    const PCLPointField *g = field (output, f.name);
    if (!g)
      continue;
    if (!(crossed && f.name == "rgb"))
      EXPECT_EQ (int (g->datatype), int (f.datatype)) << f.name;
    EXPECT_EQ (g->count, f.count) << f.name;
  }
  std::map<std::uint32_t, std::size_t> by_id;
  for (std::size_t i = 0; i < size (input); ++i)
    by_id[id (input, i)] = i;
  std::size_t mismatches = 0;
  for (std::size_t i = 0; i < size (output); ++i)
  {
    const auto it = by_id.find (id (output, i));
    if (it == by_id.end ())
    {
      ADD_FAILURE () << "output point " << i << " has an unknown id " << id (output, i);
      return origin;
    }
    origin.push_back (it->second);
    for (const auto &f : input.fields)
    {
      const PCLPointField *g = field (output, f.name);
      if (isCoordinate (f.name) || !g)
        continue;
      const std::string a = bytes (input, it->second, f), b = bytes (output, i, *g);
      const bool same = crossed && f.name == "rgb" ? colour (a) == colour (b) : a == b;
      if (!same && mismatches++ < 5)
        ADD_FAILURE () << "field " << f.name << " of point " << i << " (input " << it->second
                       << ") changed";
    }
  }
  EXPECT_EQ (mismatches, 0u);
  return origin;
}

/** Mean distance to the unit sphere of the given points of a cloud. */
double
offSphere (const PCLPointCloud2 &cloud, const std::vector<std::size_t> &points)
{
  double sum = 0.0;
  for (const auto i : points)
    sum += std::abs (std::sqrt (std::pow (coordinate (cloud, i, "x"), 2) +
                                std::pow (coordinate (cloud, i, "y"), 2) +
                                std::pow (coordinate (cloud, i, "z"), 2)) -
                     1.0);
  return sum / double (points.size ());
}

/** Files in a folder. */
std::set<std::string>
filesIn (const fs::path &dir)
{
  std::set<std::string> names;
  for (const auto &entry : fs::directory_iterator (dir))
    names.insert (entry.path ().filename ().string ());
  return names;
}

std::size_t
lines (const std::string &text)
{
  return static_cast<std::size_t> (std::count (text.begin (), text.end (), '\n'));
}

/** Every option of the tool (steps, step parameters, the others). */
const char *const every_option =
    "-outliers -tikhonov -tv -radius -sigma -threshold_ratio -degree_threshold -outlier_fraction "
    "-keep_sparse_surfaces -keep_organized -threads -k -gamma -graph_iterations -normal_displacement -local_surface "
    "-adaptive_support -patch_cover -shrinkage_correction -density_normalization -tolerance -max_iterations -solver -norm -memory_limit -removed -ascii -q "
    "-temporal -smoother -k2 -window -motion_compensation";

}  // namespace

// --- Usage -------------------------------------------------------------------------------

TEST (Cli, HelpListsEveryOptionWithItsDefault)
{
  const fs::path dir = testFolder ();
  for (const char *h : {"-h", "--help"})
  {
    const ToolRun run = runTool (dir, {h});
    ASSERT_EQ (run.code, 0) << run.err;
    std::istringstream options (every_option);
    std::string option;
    while (options >> option)
      EXPECT_TRUE (run.out.find ("  " + option + " ") != std::string::npos ||
                   run.out.find ("  " + option + "\n") != std::string::npos)
          << "-h does not list " << option;
    // The defaults are the classes' own.
    const pcl_graph_denoise::GraphTikhonovSmoothing<pcl::PointXYZ> tikhonov;
    const pcl_graph_denoise::GraphTVSmoothing<pcl::PointXYZ> tv;
    const pcl_graph_denoise::GraphDegreeOutlierRemoval<pcl::PointXYZ> outliers;
    std::ostringstream expected;
    expected << "(default: " << tikhonov.getMaximumIterations () << " -tikhonov, "
             << tv.getMaximumIterations () << " -tv)";
    EXPECT_NE (run.out.find (expected.str ()), std::string::npos) << expected.str ();
    expected.str ("");
    expected << "(default: " << tikhonov.getTolerance () << " -tikhonov, " << tv.getTolerance ()
             << " -tv;";
    EXPECT_NE (run.out.find (expected.str ()), std::string::npos) << expected.str ();
    expected.str ("");
    pcl_graph_denoise::GraphTikhonovSmoothing<pcl::PointXYZ> plain_tikhonov;
    pcl_graph_denoise::GraphTVSmoothing<pcl::PointXYZ> plain_tv;
    plain_tikhonov.setNormalDisplacement (false);
    plain_tv.setNormalDisplacement (false);
    expected << "plane: " << plain_tikhonov.getTolerance () << " -tikhonov, " << plain_tv.getTolerance ()
             << " -tv)";
    EXPECT_NE (run.out.find (expected.str ()), std::string::npos) << expected.str ();
    expected.str ("");
    expected << "(default: " << outliers.getAutomaticThresholdRatio () << ")";
    EXPECT_NE (run.out.find (expected.str ()), std::string::npos) << expected.str ();
    expected.str ("");
    expected << "(default: " << tv.getKSearch () << ")";
    EXPECT_NE (run.out.find (expected.str ()), std::string::npos) << expected.str ();
    // Every option line of the step and other options sections tells its default.
    std::istringstream text (run.out);
    std::string line;
    std::size_t option_lines = 0;
    bool in_options = false;
    while (std::getline (text, line))
    {
      if (line.find ("options") != std::string::npos && line.back () == ':')
        in_options = true;
      if (in_options && line.rfind ("  -", 0) == 0 && line.find ("-h, --help") == std::string::npos)
      {
        ++option_lines;
        // The default is on the option's line or on the next ones.
        std::string rest = line;
        std::streampos at = text.tellg ();
        std::string next;
        for (int n = 0; n < 3 && std::getline (text, next) && next.rfind ("  -", 0) != 0; ++n)
          rest += next;
        text.seekg (at);
        EXPECT_NE (rest.find ("default"), std::string::npos) << "no default for: " << line;
      }
    }
    EXPECT_GE (option_lines, 22u);
  }
}

// --- Fields, points and organisation -----------------------------------------------------

TEST (Cli, DefaultChainKeepsEveryOtherFieldAndSplitsThePoints)
{
  const fs::path dir = testFolder ();
  const PCLPointCloud2 input = sphereWithOutliers ();
  savePcd (dir / "in.pcd", input);
  const std::vector<std::string> args = {"in.pcd", "out.pcd", "-removed", "removed.pcd"};
  const ToolRun run = runTool (dir, args);
  ASSERT_EQ (run.code, 0) << describe (args, run);

  const PCLPointCloud2 output = load (dir / "out.pcd"), removed = load (dir / "removed.pcd");
  EXPECT_LT (size (output), size (input));
  EXPECT_GT (size (removed), 0u);
  EXPECT_EQ (size (output) + size (removed), size (input));
  const auto kept = expectFieldsKept (input, output);
  const auto gone = expectFieldsKept (input, removed);
  std::set<std::size_t> all (kept.begin (), kept.end ());
  all.insert (gone.begin (), gone.end ());
  EXPECT_EQ (all.size (), size (input)) << "a point is in both files or in neither";
  // Kept points keep their order.
  EXPECT_TRUE (std::is_sorted (kept.begin (), kept.end ()));
  // Most injected outliers (the last 100 points) are removed, few sphere points are.
  const std::size_t surface = 2000;
  const auto outliers_removed =
      std::count_if (gone.begin (), gone.end (), [&] (std::size_t i) { return i >= surface; });
  EXPECT_GT (outliers_removed, 60);
  EXPECT_LT (gone.size () - static_cast<std::size_t> (outliers_removed), 40u);
  // The smoothing moved the kept sphere points closer to the sphere.
  std::vector<std::size_t> on_sphere_in, on_sphere_out;
  for (std::size_t i = 0; i < kept.size (); ++i)
    if (kept[i] < surface)
    {
      on_sphere_in.push_back (kept[i]);
      on_sphere_out.push_back (i);
    }
  EXPECT_LT (offSphere (output, on_sphere_out), 0.8 * offSphere (input, on_sphere_in));

  // The report: both steps, each with its time, the counts and the solver's figures.
  EXPECT_EQ (run.out, "");
  for (const char *part :
       {"Loading ", "Step 1/2: -outliers (GraphDegreeOutlierRemoval), default chain",
        "Step 2/2: -tv (GraphTVSmoothing), default chain", " ms]", "iterations, residual",
        "converged", "Saving out.pcd (binary)", "Saving removed.pcd (binary)"})
    EXPECT_NE (run.err.find (part), std::string::npos) << "report lacks '" << part << "':\n"
                                                       << run.err;
  const std::string counts = "removed " + std::to_string (size (removed)) + " of " +
                             std::to_string (size (input)) + " points";
  EXPECT_NE (run.err.find (counts), std::string::npos) << counts << "\n" << run.err;
  // Nothing but the two outputs (and the input) in the folder.
  EXPECT_EQ (filesIn (dir), (std::set<std::string>{"in.pcd", "out.pcd", "removed.pcd"}));
}

TEST (Cli, SmoothingKeepsSizeOrderOrganisationFieldsAndNonFinitePoints)
{
  const fs::path dir = testFolder ();
  const PCLPointCloud2 input = organisedPlane ();
  savePcd (dir / "in.pcd", input);
  const std::vector<std::vector<std::string>> chains = {
      {"-tv"}, {"-tikhonov"}, {"-tikhonov", "-tv"}, {"-tv", "-tv"}, {"-tv", "gamma=0.02,k=8"}};
  for (const auto &chain : chains)
  {
    std::vector<std::string> args = {"in.pcd", "out.pcd"};
    args.insert (args.end (), chain.begin (), chain.end ());
    const ToolRun run = runTool (dir, args);
    ASSERT_EQ (run.code, 0) << describe (args, run);
    const PCLPointCloud2 output = load (dir / "out.pcd");
    EXPECT_EQ (output.width, input.width);
    EXPECT_EQ (output.height, input.height);
    const auto origin = expectFieldsKept (input, output);
    ASSERT_EQ (origin.size (), size (input));
    std::size_t moved = 0, nan = 0;
    for (std::size_t i = 0; i < origin.size (); ++i)
    {
      EXPECT_EQ (origin[i], i) << "points reordered";
      if (!finite (input, i))
      {
        ++nan;
        for (const char *c : {"x", "y", "z"})
          EXPECT_EQ (bytes (output, i, *field (output, c)), bytes (input, i, *field (input, c)))
              << "a non-finite point changed";
        continue;
      }
      moved += coordinate (output, i, "z") != coordinate (input, i, "z");
      EXPECT_LT (std::abs (coordinate (output, i, "z")), 0.1);
    }
    EXPECT_GT (nan, 0u);
    EXPECT_GT (moved, origin.size () / 2) << describe (args, run);
    const auto steps = std::count_if (chain.begin (), chain.end (), [] (const std::string &a) {
      return a == "-tv" || a == "-tikhonov";
    });
    const std::string last = "Step " + std::to_string (steps) + "/" + std::to_string (steps) + ": ";
    EXPECT_NE (run.err.find (last), std::string::npos) << run.err;
  }
}

TEST (Cli, DoubleCoordinatesStayDoublesAndMoveByTheDisplacement)
{
  const fs::path dir = testFolder ();
  const PCLPointCloud2 input = organisedPlane (PCLPointField::FLOAT64);
  savePcd (dir / "in.pcd", input);
  const std::vector<std::string> args = {"in.pcd", "out.pcd", "-tv"};
  const ToolRun run = runTool (dir, args);
  ASSERT_EQ (run.code, 0) << describe (args, run);
  const PCLPointCloud2 output = load (dir / "out.pcd");
  ASSERT_EQ (size (output), size (input));
  EXPECT_EQ (int (field (output, "x")->datatype), int (PCLPointField::FLOAT64));
  expectFieldsKept (input, output);
  std::size_t moved = 0;
  for (std::size_t i = 0; i < size (input); ++i)
  {
    if (!finite (input, i))
      continue;
    // x and y barely move on a plane (the normal is z): the double's digits beyond a
    // float's survive.
    const double dx = coordinate (output, i, "x") - coordinate (input, i, "x");
    EXPECT_LT (std::abs (dx), 0.01);
    moved += coordinate (output, i, "z") != coordinate (input, i, "z");
  }
  EXPECT_GT (moved, size (input) / 2);
}

/** `cloud` (double x, y, z) moved by `shift`. */
PCLPointCloud2
shifted (PCLPointCloud2 cloud, const Eigen::Vector3d &shift)
{
  const char *names[3] = {"x", "y", "z"};
  for (std::size_t i = 0; i < size (cloud); ++i)
    for (int d = 0; d < 3; ++d)
    {
      const PCLPointField &f = *field (cloud, names[d]);
      std::uint8_t *p = cloud.data.data () + (i / cloud.width) * cloud.row_step +
                        (i % cloud.width) * cloud.point_step + f.offset;
      double v;
      std::memcpy (&v, p, 8);
      v += shift[d];
      std::memcpy (p, &v, 8);
    }
  return cloud;
}

TEST (Cli, GeoReferencedDoubleCoordinatesKeepTheirPrecision)
{
  // A sphere of radius 1 with UTM-like coordinates (4,000 km north): as floats its y
  // steps by 0.25 and the tool saw a cloud without noise, and moved nothing. The tool
  // works about the centre of the doubles instead: the same result as at the origin,
  // for one file and for the frames of a sequence.
  const fs::path dir = testFolder ();
  const Eigen::Vector3d far (500000.0, 4000000.0, 100.0);
  std::vector<PCLPointCloud2> near_frames, far_frames;
  for (std::uint64_t t = 0; t < 2; ++t)
  {
    const auto xyz = pcl_graph_denoise::synthetic::noisySphere (1500, 1.0, 0.01, 30 + t);
    near_frames.push_back (makeCloud (xyz, PCLPointField::FLOAT64, static_cast<std::uint32_t> (xyz.size ()), 1));
    far_frames.push_back (shifted (near_frames.back (), far));
    savePcd (dir / ("near" + std::to_string (t) + ".pcd"), near_frames.back ());
    savePcd (dir / ("far" + std::to_string (t) + ".pcd"), far_frames.back ());
  }
  fs::create_directories (dir / "near_out");
  fs::create_directories (dir / "far_out");
  // The runs at the origin and far away, and the first frame's output of each.
  struct Case
  {
    std::vector<std::string> near_args, far_args;
    std::string near_output, far_output;
  };
  const std::vector<Case> cases = {
      {{"near0.pcd", "near_tv.pcd", "-tv"}, {"far0.pcd", "far_tv.pcd", "-tv"}, "near_tv.pcd", "far_tv.pcd"},
      {{"near0.pcd", "near1.pcd", "near_out", "-temporal"},
       {"far0.pcd", "far1.pcd", "far_out", "-temporal"},
       "near_out/near0.pcd",
       "far_out/far0.pcd"}};
  for (const Case &c : cases)
  {
    for (const auto *args : {&c.near_args, &c.far_args})
    {
      const ToolRun run = runTool (dir, *args);
      ASSERT_EQ (run.code, 0) << describe (*args, run);
    }
    const PCLPointCloud2 near_out = load (dir / c.near_output);
    const PCLPointCloud2 far_out = load (dir / c.far_output);
    const PCLPointCloud2 &near_in = near_frames[0];
    ASSERT_EQ (size (far_out), size (near_in));
    double moved = 0.0, differ = 0.0;
    const char *names[3] = {"x", "y", "z"};
    for (std::size_t i = 0; i < size (near_in); ++i)
      for (int d = 0; d < 3; ++d)
      {
        const double near_move = coordinate (near_out, i, names[d]) - coordinate (near_in, i, names[d]);
        const double far_move = coordinate (far_out, i, names[d]) - far[d] - coordinate (near_in, i, names[d]);
        moved += std::abs (near_move);
        differ += std::abs (far_move - near_move);
      }
    EXPECT_GT (moved / double (size (near_in)), 0.003) << c.near_args.back ();
    EXPECT_LT (differ, 0.01 * moved) << c.near_args.back ();
  }
  // With one stray point at (0, 0, 0), thousands of km from the far sphere (as some
  // exports write): the sphere comes out as accurate as at the origin without it (the
  // origin was the centre of the bounding box, 2,000 km from the sphere, where a float
  // steps by 0.125, and the sphere came out worse than it went in). Its points need not
  // move exactly as there: the far point changes the graph's Morton order, and with it
  // which vertices fit a quadric.
  auto stray = pcl_graph_denoise::synthetic::noisySphere (1500, 1.0, 0.01, 30);
  stray.push_back (pcl::PointXYZ (float (-far[0]), float (-far[1]), float (-far[2])));
  savePcd (dir / "far_stray.pcd",
           shifted (makeCloud (stray, PCLPointField::FLOAT64, static_cast<std::uint32_t> (stray.size ()), 1),
                    far));
  const std::vector<std::string> args = {"far_stray.pcd", "far_stray_tv.pcd", "-tv"};
  const ToolRun run = runTool (dir, args);
  ASSERT_EQ (run.code, 0) << describe (args, run);
  const PCLPointCloud2 &near_in = near_frames[0];
  const PCLPointCloud2 far_out = load (dir / "far_stray_tv.pcd");
  ASSERT_EQ (size (far_out), size (near_in) + 1);
  // Mean distance to the sphere of the input, of the output at the origin, and far away.
  const auto error = [&] (const PCLPointCloud2 &cloud, const Eigen::Vector3d &centre) {
    double sum = 0.0;
    for (std::size_t i = 0; i < size (near_in); ++i)
    {
      const Eigen::Vector3d p (coordinate (cloud, i, "x"), coordinate (cloud, i, "y"),
                               coordinate (cloud, i, "z"));
      sum += std::abs ((p - centre).norm () - 1.0);
    }
    return sum / double (size (near_in));
  };
  const double noisy = error (near_in, Eigen::Vector3d::Zero ());
  const double near_error = error (load (dir / "near_tv.pcd"), Eigen::Vector3d::Zero ());
  const double far_error = error (far_out, far);
  EXPECT_LT (near_error, 0.5 * noisy);
  EXPECT_LT (far_error, 1.1 * near_error) << "at the origin " << near_error << ", input " << noisy;
  // The stray point, alone, stays where it was, to the bit.
  for (const char *name : {"x", "y", "z"})
    EXPECT_EQ (coordinate (far_out, size (near_in), name), 0.0);
}

TEST (Cli, RemovedMayNotNameTheInput)
{
  const fs::path dir = testFolder ();
  savePcd (dir / "in.pcd", sphereWithOutliers ());
  const std::string before = readFile (dir / "in.pcd");
  for (const std::string &removed : {"in.pcd", "./in.pcd"})
  {
    const std::vector<std::string> args = {"in.pcd", "out.pcd", "-outliers", "-removed", removed};
    const ToolRun run = runTool (dir, args);
    EXPECT_EQ (run.code, 2) << describe (args, run);
    EXPECT_NE (run.err.find ("-removed names the input file"), std::string::npos) << run.err;
    EXPECT_EQ (readFile (dir / "in.pcd"), before);
    EXPECT_FALSE (fs::exists (dir / "out.pcd"));
  }
}

TEST (Cli, GammaZeroIsTheIdentityInBothSyntaxes)
{
  const fs::path dir = testFolder ();
  const PCLPointCloud2 input = organisedPlane ();
  savePcd (dir / "in.pcd", input);
  const std::vector<std::vector<std::string>> chains = {
      {"-tv", "-gamma", "0"}, {"-tikhonov", "gamma=0,k=5"}, {"-gamma", "0", "-tv", "-tikhonov"}};
  for (const auto &chain : chains)
  {
    std::vector<std::string> args = {"in.pcd", "out.pcd"};
    args.insert (args.end (), chain.begin (), chain.end ());
    const ToolRun run = runTool (dir, args);
    ASSERT_EQ (run.code, 0) << describe (args, run);
    const PCLPointCloud2 output = load (dir / "out.pcd");
    ASSERT_EQ (size (output), size (input));
    EXPECT_TRUE (output.data == input.data) << describe (args, run);
    EXPECT_NE (run.err.find ("gamma 0"), std::string::npos) << run.err;
    EXPECT_NE (run.err.find (" 0 moved"), std::string::npos) << run.err;
  }
  // And without it the same chains move points: the parameter made the difference.
  const std::vector<std::string> args = {"in.pcd", "out.pcd", "-tikhonov", "k=5"};
  const ToolRun run = runTool (dir, args);
  ASSERT_EQ (run.code, 0) << describe (args, run);
  EXPECT_FALSE (load (dir / "out.pcd").data == input.data);
}

TEST (Cli, OutlierParametersReachTheFilter)
{
  const fs::path dir = testFolder ();
  const PCLPointCloud2 input = sphereWithOutliers ();
  savePcd (dir / "in.pcd", input);
  // The percentile rule removes exactly round(p x count) points; the removed points go
  // to a PLY file, with all their fields.
  for (const double p : {0.1, 0.03})
  {
    const std::vector<std::string> args = {
        "in.pcd",           "out.pcd",  "-outliers",  "-outlier_fraction",
        std::to_string (p), "-removed", "removed.ply"};
    const ToolRun run = runTool (dir, args);
    ASSERT_EQ (run.code, 0) << describe (args, run);
    const PCLPointCloud2 output = load (dir / "out.pcd"), removed = load (dir / "removed.ply");
    const auto expected_removed =
        static_cast<std::size_t> (std::llround (p * double (size (input))));
    EXPECT_EQ (size (removed), expected_removed);
    EXPECT_EQ (size (output), size (input) - expected_removed);
    // Outlier removal alone moves no point.
    const auto kept = expectFieldsKept (input, output);
    for (std::size_t i = 0; i < kept.size (); ++i)
      for (const char *c : {"x", "y", "z"})
        ASSERT_EQ (bytes (output, i, *field (output, c)),
                   bytes (input, kept[i], *field (input, c)));
    const auto gone = expectFieldsKept (input, removed, Formats::CROSSED);
    std::set<std::size_t> all (kept.begin (), kept.end ());
    all.insert (gone.begin (), gone.end ());
    EXPECT_EQ (all.size (), size (input));
  }
  // A threshold of 0 without the residual test removes nothing (there is no non-finite
  // point): the removed file exists and is empty, in both formats.
  for (const std::string removed_file : {"removed.pcd", "removed.ply"})
  {
    const std::vector<std::string> args = {"in.pcd",        "out.pcd",
                                           "-outliers",     "degree_threshold=0,residual_threshold=0",
                                           "-removed",      removed_file};
    const ToolRun run = runTool (dir, args);
    ASSERT_EQ (run.code, 0) << describe (args, run);
    EXPECT_EQ (size (load (dir / "out.pcd")), size (input));
    ASSERT_TRUE (fs::exists (dir / removed_file));
    PCLPointCloud2 removed;
    if (removed_file == "removed.ply")
      EXPECT_EQ (pcl::io::loadPLYFile ((dir / removed_file).string (), removed), 0);
    else
      pcl::io::loadPCDFile ((dir / removed_file).string (), removed);
    EXPECT_EQ (size (removed), 0u);
  }
}

TEST (Cli, ResidualThresholdReachesTheFilter)
{
  const fs::path dir = testFolder ();
  const PCLPointCloud2 input = sphereWithOutliers ();
  savePcd (dir / "in.pcd", input);
  pcl::PointCloud<pcl::PointXYZ>::Ptr xyz (new pcl::PointCloud<pcl::PointXYZ>);
  pcl::fromPCLPointCloud2 (input, *xyz);
  // With no degree threshold, what goes is the residual test's alone (the outliers close
  // to the sphere, and a multiplier of 1 takes a few surface points), as in the library.
  pcl_graph_denoise::GraphDegreeOutlierRemoval<pcl::PointXYZ> filter;
  filter.setInputCloud (xyz);
  filter.setDegreeThreshold (0.0);
  filter.setResidualThreshold (1.0);
  pcl::Indices kept;
  filter.filter (kept);
  ASSERT_LT (kept.size (), xyz->size () - 5);
  for (const std::vector<std::string> &step :
       {std::vector<std::string>{"-outliers", "-degree_threshold", "0", "-residual_threshold", "1"},
        {"-outliers", "degree_threshold=0,residual_threshold=1"}})
  {
    std::vector<std::string> args = {"in.pcd", "out.pcd"};
    args.insert (args.end (), step.begin (), step.end ());
    const ToolRun run = runTool (dir, args);
    ASSERT_EQ (run.code, 0) << describe (args, run);
    EXPECT_EQ (size (load (dir / "out.pcd")), kept.size ());
    EXPECT_NE (run.err.find ("residual test 1 x noise scale"), std::string::npos) << run.err;
  }
  // Off: nothing goes, and the report does not mention it.
  const ToolRun off = runTool (
      dir, {"in.pcd", "out.pcd", "-outliers", "degree_threshold=0,residual_threshold=0"});
  ASSERT_EQ (off.code, 0);
  EXPECT_EQ (size (load (dir / "out.pcd")), size (input));
  EXPECT_EQ (off.err.find ("residual test"), std::string::npos) << off.err;
  EXPECT_EQ (runTool (dir, {"in.pcd", "out.pcd", "-outliers", "-residual_threshold", "-1"}).code, 2);
}

TEST (Cli, KeepSparseSurfacesReachesTheFilter)
{
  const fs::path dir = testFolder ();
  std::vector<pcl_graph_denoise::testing::FloorPart> parts;
  const auto floor = std::make_shared<pcl::PointCloud<pcl::PointXYZ>> (
      pcl_graph_denoise::testing::recedingFloor (300, 4, parts));
  PCLPointCloud2 input;
  pcl::toPCLPointCloud2 (*floor, input);
  savePcd (dir / "in.pcd", input);
  pcl_graph_denoise::GraphDegreeOutlierRemoval<pcl::PointXYZ> filter;
  filter.setInputCloud (floor);
  for (const bool keep : {true, false})
  {
    filter.setKeepSparseSurfaces (keep);
    pcl::Indices kept;
    filter.filter (kept);
    const std::string value = keep ? "1" : "0";
    for (const std::vector<std::string> &step :
         {std::vector<std::string>{"-outliers", "-keep_sparse_surfaces", value},
          {"-outliers", "keep_sparse_surfaces=" + value}})
    {
      std::vector<std::string> args = {"in.pcd", "out.pcd"};
      args.insert (args.end (), step.begin (), step.end ());
      const ToolRun run = runTool (dir, args);
      ASSERT_EQ (run.code, 0) << describe (args, run);
      EXPECT_EQ (size (load (dir / "out.pcd")), kept.size ()) << value;
    }
  }
  // The default keeps them, and far more points than without.
  ASSERT_EQ (runTool (dir, {"in.pcd", "out.pcd", "-outliers"}).code, 0);
  const std::size_t with = size (load (dir / "out.pcd"));
  ASSERT_EQ (runTool (dir, {"in.pcd", "out.pcd", "-outliers", "-keep_sparse_surfaces", "0"}).code, 0);
  EXPECT_GT (with, size (load (dir / "out.pcd")) + 100);
  EXPECT_EQ (runTool (dir, {"in.pcd", "out.pcd", "-outliers", "-keep_sparse_surfaces", "2"}).code, 2);
}

TEST (Cli, OutliersOnAnOrganisedCloud)
{
  const fs::path dir = testFolder ();
  const PCLPointCloud2 input = organisedPlane ();
  savePcd (dir / "in.pcd", input);
  std::size_t non_finite = 0;
  for (std::size_t i = 0; i < size (input); ++i)
    non_finite += !finite (input, i);

  // Dropped: the non-finite points go with the outliers, the result is unorganised.
  std::vector<std::string> args = {"in.pcd", "out.pcd",  "-outliers",  "-outlier_fraction",
                                   "0.05",   "-removed", "removed.pcd"};
  ToolRun run = runTool (dir, args);
  ASSERT_EQ (run.code, 0) << describe (args, run);
  PCLPointCloud2 output = load (dir / "out.pcd"), removed = load (dir / "removed.pcd");
  const std::size_t outliers =
      static_cast<std::size_t> (std::llround (0.05 * double (size (input) - non_finite)));
  EXPECT_EQ (output.height, 1u);
  EXPECT_EQ (size (removed), outliers + non_finite);
  EXPECT_EQ (size (output) + size (removed), size (input));

  // Kept organised: every point stays, the removed ones with a NaN x, y, z.
  args = {"in.pcd",          "out.pcd", "-outliers", "-outlier_fraction", "0.05",
          "-keep_organized", "1",       "-removed",  "removed.pcd"};
  run = runTool (dir, args);
  ASSERT_EQ (run.code, 0) << describe (args, run);
  output = load (dir / "out.pcd");
  removed = load (dir / "removed.pcd");
  EXPECT_EQ (output.width, input.width);
  EXPECT_EQ (output.height, input.height);
  expectFieldsKept (input, output);
  std::size_t nan = 0;
  for (std::size_t i = 0; i < size (output); ++i)
    nan += !finite (output, i);
  EXPECT_EQ (nan, outliers + non_finite);
  EXPECT_EQ (size (removed), outliers + non_finite);
}

// --- Formats -----------------------------------------------------------------------------

TEST (Cli, AsciiAndBinaryOutputsHoldTheSameCloud)
{
  const fs::path dir = testFolder ();
  const PCLPointCloud2 input = organisedPlane ();
  savePcd (dir / "in.pcd", input);
  const auto header = [&] (const char *name) { return readFile (dir / name).substr (0, 600); };
  struct Case
  {
    std::vector<std::string> extra;
    const char *file, *marker;
  };
  const std::vector<Case> cases = {
      {{}, "binary.pcd", "DATA binary\n"},
      {{"-ascii"}, "ascii.pcd", "DATA ascii\n"},
      {{"-ascii", "1"}, "ascii1.pcd", "DATA ascii\n"},
      {{"-ascii", "0"}, "binary0.pcd", "DATA binary\n"},
      {{}, "binary.ply", "format binary_little_endian 1.0"},
      {{"-ascii"}, "ascii.ply", "format ascii 1.0"},
  };
  for (const auto &c : cases)
  {
    // One gamma for all: the clouds compared below are the same smoothing.
    std::vector<std::string> args = {"in.pcd", c.file, "-tv", "-gamma", "0.01", "-threads", "1"};
    args.insert (args.end (), c.extra.begin (), c.extra.end ());
    const ToolRun run = runTool (dir, args);
    ASSERT_EQ (run.code, 0) << describe (args, run);
    EXPECT_NE (header (c.file).find (c.marker), std::string::npos) << c.file << ":\n"
                                                                   << header (c.file);
    const PCLPointCloud2 output = load (dir / c.file);
    EXPECT_EQ (size (output), size (input)) << c.file;
    // The organisation too (PCL's PLY files keep it in their camera element).
    EXPECT_EQ (output.width, input.width) << c.file;
    EXPECT_EQ (output.height, input.height) << c.file;
    const bool binary_pcd = std::string (c.marker) == "DATA binary\n";
    expectFieldsKept (input, output, binary_pcd ? Formats::SAME : Formats::CROSSED);
  }
  // The ASCII files hold exactly the binary ones' values (floats written with 9 digits,
  // doubles with 17).
  const PCLPointCloud2 binary = load (dir / "binary.pcd"), ascii = load (dir / "ascii.pcd");
  std::size_t different = 0;
  for (std::size_t i = 0; i < size (binary); ++i)
    for (const auto &f : binary.fields)
    {
      const std::string a = bytes (binary, i, f), b = bytes (ascii, i, *field (ascii, f.name));
      const bool both_nan = isCoordinate (f.name) && !finite (binary, i) && !finite (ascii, i);
      different += a != b && !both_nan;
    }
  EXPECT_EQ (different, 0u);
}

TEST (Cli, PlyInPlyAndPcdOut)
{
  const fs::path dir = testFolder ();
  savePly (dir / "in.ply", sphereWithOutliers ());
  savePly (dir / "in_ascii.ply", sphereWithOutliers (), false);
  const PCLPointCloud2 input = load (dir / "in.ply");
  ASSERT_EQ (size (input), 2100u);
  ASSERT_NE (field (input, "intensity"), nullptr);
  for (const char *in : {"in.ply", "in_ascii.ply"})
    for (const char *out : {"out.ply", "out.pcd"})
    {
      // Compared with the input as PCL reads it (the test wrote in_ascii.ply with PCL's
      // default precision, which rounds the doubles).
      const PCLPointCloud2 input = load (dir / in);
      const std::vector<std::string> args = {in, out, "-tikhonov"};
      const ToolRun run = runTool (dir, args);
      ASSERT_EQ (run.code, 0) << describe (args, run);
      const PCLPointCloud2 output = load (dir / out);
      ASSERT_EQ (size (output), size (input)) << out;
      const auto origin = expectFieldsKept (input, output);
      for (std::size_t i = 0; i < origin.size (); ++i)
        ASSERT_EQ (origin[i], i);
    }
  // With the outliers removed, PLY to PLY, and the removed points in PLY too.
  const std::vector<std::string> args = {"in.ply", "out.ply", "-outliers", "-removed", "gone.ply"};
  const ToolRun run = runTool (dir, args);
  ASSERT_EQ (run.code, 0) << describe (args, run);
  const PCLPointCloud2 output = load (dir / "out.ply"), removed = load (dir / "gone.ply");
  EXPECT_EQ (size (output) + size (removed), size (input));
  EXPECT_GT (size (removed), 0u);
  expectFieldsKept (input, output);
  expectFieldsKept (input, removed);
}

TEST (Cli, QuietPrintsNothing)
{
  const fs::path dir = testFolder ();
  savePcd (dir / "in.pcd", sphereWithOutliers ());
  const std::vector<std::string> args = {"in.pcd", "out.pcd", "-q"};
  const ToolRun run = runTool (dir, args);
  ASSERT_EQ (run.code, 0) << describe (args, run);
  EXPECT_EQ (run.out, "");
  EXPECT_EQ (run.err, "");
  EXPECT_TRUE (fs::exists (dir / "out.pcd"));
}

// --- Bad input ---------------------------------------------------------------------------

/** Every failure: a non-zero exit code, one line on stderr, no output file, nothing
 *  left in the folder but what was there. */
TEST (Cli, BadInputFailsWithOneLineAndNoOutput)
{
  const fs::path dir = testFolder ();
  const PCLPointCloud2 good = sphereWithOutliers ();
  savePcd (dir / "good.pcd", good);
  savePcd (dir / "good_ascii.pcd", good, false);
  savePly (dir / "good.ply", good);
  const std::string binary = readFile (dir / "good.pcd"), ascii = readFile (dir / "good_ascii.pcd"),
                    ply = readFile (dir / "good.ply");
  const auto write = [&] (const char *name, const std::string &content) {
    std::ofstream (dir / name, std::ios::binary) << content;
  };
  write ("truncated.pcd", binary.substr (0, binary.size () / 2));
  write ("truncated_header.pcd", binary.substr (0, 60));
  write ("truncated_ascii.pcd", ascii.substr (0, ascii.size () * 2 / 3));
  write ("truncated.ply", ply.substr (0, ply.size () / 2));
  write ("text.pcd", "hello, this is not a point cloud\n");
  write ("text.ply", "hello, this is not a point cloud\n");
  std::string noise;
  for (int i = 0; i < 3000; ++i)
    noise += static_cast<char> ((i * 7919 + 13) % 256);
  write ("noise.pcd", noise);
  write ("noise.ply", noise);
  write ("empty_file.pcd", "");
  const std::string pcd_header = "# .PCD v0.7\nVERSION 0.7\nFIELDS x y z\nSIZE 4 4 4\nTYPE F F F\n"
                                 "COUNT 1 1 1\n";
  write ("bad_type.pcd", "# .PCD v0.7\nVERSION 0.7\nFIELDS x y z\nSIZE 4 4 4\nTYPE F Q F\n"
                         "COUNT 1 1 1\nWIDTH 2\nHEIGHT 1\nPOINTS 2\nDATA ascii\n1 2 3\n4 5 6\n");
  write ("huge.pcd", pcd_header + "WIDTH 2000000000\nHEIGHT 1\nPOINTS 2000000000\nDATA binary\n"
                                  "0123456789ab");
  write ("no_xyz.pcd", "# .PCD v0.7\nVERSION 0.7\nFIELDS a b c\nSIZE 4 4 4\nTYPE F F F\n"
                       "COUNT 1 1 1\nWIDTH 2\nHEIGHT 1\nPOINTS 2\nDATA ascii\n1 2 3\n4 5 6\n");
  write ("integer_xyz.pcd", "# .PCD v0.7\nVERSION 0.7\nFIELDS x y z\nSIZE 4 4 4\nTYPE I I I\n"
                            "COUNT 1 1 1\nWIDTH 2\nHEIGHT 1\nPOINTS 2\nDATA ascii\n1 2 3\n4 5 6\n");
  write ("no_xyz.ply", "ply\nformat ascii 1.0\nelement vertex 2\nproperty float a\n"
                       "property float b\nend_header\n1 2\n3 4\n");
  write ("empty.pcd", pcd_header + "WIDTH 0\nHEIGHT 1\nPOINTS 0\nDATA ascii\n");
  write ("empty.ply", "ply\nformat ascii 1.0\nelement vertex 0\nproperty float x\n"
                      "property float y\nproperty float z\nend_header\n");
  write ("all_nan.pcd",
         pcd_header + "WIDTH 2\nHEIGHT 1\nPOINTS 2\nDATA ascii\nnan nan nan\nnan nan nan\n");
  // Data that PCL's header parser, which reads on after DATA, takes for header lines: it
  // redefined the fields of a cloud already sized and PCL's reader crashed (SIGSEGV; found
  // by fuzz/fuzz_cloud_file, fuzz/corpus/fuzz_cloud_file/crash-pcd-header-line-after-data).
  write ("header_after_data.pcd",
         "#at\nFIELDS x y zTYPE\nSIZE 4 4 8\nTYPE F F F\nCOUNT 1 1 1\nWIDTH 20\nHEIGHT 1\n"
         "VIEWPOINT 0 0 0 1 0 0 0\nPOINTS 20\nDATA ascii\n"
         "COLUMNS0000000 00000000 00000000000000000000\nVERSION 000000000\n"
         "COLUMNS000000000000\n00000000 000000000 00000000000000000");
  write ("points_after_data.pcd", pcd_header + "WIDTH 2\nHEIGHT 1\nPOINTS 2\nDATA binary\n"
                                             "\n# comment\nPOINTS 900000000\n" +
                                             std::string (24, '\0'));
  write ("in.xyz", "1 2 3\n");
  fs::create_directories (dir / "folder.pcd");

  const std::vector<std::vector<std::string>> cases = {
      // Files.
      {"missing.pcd", "out.pcd"},
      {"missing.ply", "out.ply"},
      {"folder.pcd", "out.pcd"},
      {"truncated.pcd", "out.pcd"},
      {"truncated_header.pcd", "out.pcd"},
      {"truncated_ascii.pcd", "out.pcd"},
      {"truncated.ply", "out.ply"},
      {"text.pcd", "out.pcd"},
      {"text.ply", "out.pcd"},
      {"noise.pcd", "out.pcd"},
      {"noise.ply", "out.pcd"},
      {"empty_file.pcd", "out.pcd"},
      {"bad_type.pcd", "out.pcd"},
      {"huge.pcd", "out.pcd"},
      {"no_xyz.pcd", "out.pcd"},
      {"integer_xyz.pcd", "out.pcd"},
      {"no_xyz.ply", "out.pcd"},
      {"empty.pcd", "out.pcd"},
      {"empty.ply", "out.pcd"},
      {"all_nan.pcd", "out.pcd"},
      {"header_after_data.pcd", "out.pcd"},
      {"points_after_data.pcd", "out.pcd"},
      {"in.xyz", "out.pcd"},
      {"good.pcd", "out.txt"},
      {"good.pcd", "out"},
      {"good.pcd", "missing_folder/out.pcd"},
      {"good.pcd", "folder.pcd"},
      {"good.pcd", "out.pcd", "-removed", "removed.xyz", "-outliers"},
      // Command line.
      {},
      {"good.pcd"},
      {"good.pcd", "out.pcd", "extra.pcd"},
      {"good.pcd", "out.pcd", "-foo"},
      {"good.pcd", "out.pcd", "--tv"},
      {"good.pcd", "out.pcd", "-tv", "-gamma"},
      {"good.pcd", "out.pcd", "-tv", "-gamma", "abc"},
      {"good.pcd", "out.pcd", "-tv", "-gamma", "-1"},
      {"good.pcd", "out.pcd", "-tv", "-gamma", "nan"},
      {"good.pcd", "out.pcd", "-tv", "-gamma", "inf"},
      {"good.pcd", "out.pcd", "-tv", "-gamma", "1e999"},
      {"good.pcd", "out.pcd", "-tv", "-gamma", "0x10"},  // strtod would read 16
      {"good.pcd", "out.pcd", "-tv", "gamma=0x1p-4"},
      {"good.pcd", "out.pcd", "-outliers", "-radius", "infinity"},
      {"good.pcd", "out.pcd", "-tv", "-sigma", "-0.5"},
      {"good.pcd", "out.pcd", "-tv", "-k", "0"},
      {"good.pcd", "out.pcd", "-tv", "-k", "2.5"},
      {"good.pcd", "out.pcd", "-tv", "-k", "-3"},
      {"good.pcd", "out.pcd", "-tv", "-k", "99999999999"},
      {"good.pcd", "out.pcd", "-tv", "-tolerance", "0"},
      {"good.pcd", "out.pcd", "-tv", "-max_iterations", "0"},
      {"good.pcd", "out.pcd", "-tv", "-graph_iterations", "x"},
      {"good.pcd", "out.pcd", "-tv", "-graph_iterations", "1001"},
      {"good.pcd", "out.pcd", "-tv", "-graph_iterations", "2147483647"},
      {"good.pcd", "out.pcd", "-tv", "-normal_displacement", "maybe"},
      {"good.pcd", "out.pcd", "-tv", "-norm", "euclidean"},
      {"good.pcd", "out.pcd", "-tv", "-local_surface", "sphere"},
      {"good.pcd", "out.pcd", "-tikhonov", "-solver", "lu"},
      {"good.pcd", "out.pcd", "-tv", "-solver", "cg"},
      {"good.pcd", "out.pcd", "-tv", "-threads", "-1"},
      {"good.pcd", "out.pcd", "-tv", "gamma=abc"},
      {"good.pcd", "out.pcd", "-tv", "gamma=0.1,foo=2"},
      {"good.pcd", "out.pcd", "-tv", "gamma"},
      {"good.pcd", "out.pcd", "-tv", "-gamma", "0.1", "-gamma", "0.2"},
      {"good.pcd", "out.pcd", "-outliers", "-outlier_fraction", "1.5"},
      {"good.pcd", "out.pcd", "-outliers", "-radius", "-2"},
      {"good.pcd", "out.pcd", "-outliers", "-degree_threshold", "1", "-outlier_fraction", "0.1"},
      {"good.pcd", "out.pcd", "-outliers", "-gamma", "0.1"},
      {"good.pcd", "out.pcd", "-outliers", "-keep_organized", "2"},
      {"good.pcd", "out.pcd", "-k", "5", "-outliers"},
      {"good.pcd", "out.pcd", "-tv", "-removed", "removed.pcd"},
      {"good.pcd", "out.pcd", "-outliers", "-removed", "out.pcd"},
      {"good.pcd", "out.pcd", "-outliers", "-removed", "./out.pcd"},
      {"good.pcd", "out.pcd", "-degree_threshold", "1", "-outlier_fraction", "0.1", "-outliers"},
      {"good.pcd", "out.pcd", "-outliers", "-removed"},
  };
  const std::set<std::string> before = filesIn (dir);
  for (const auto &args : cases)
  {
    const ToolRun run = runTool (dir, args);
    const std::string what = describe (args, run);
    EXPECT_NE (run.code, 0) << what;
    EXPECT_LT (run.code, 128) << "crashed: " << what;
    EXPECT_EQ (lines (run.err), 1u) << what;
    EXPECT_EQ (run.err.rfind ("pcl_graph_denoise: error: ", 0), 0u) << what;
    EXPECT_GT (run.err.size (), std::string ("pcl_graph_denoise: error: ").size () + 10) << what;
    EXPECT_EQ (filesIn (dir), before) << "files left behind by: " << what;
  }

  // A chain that removes every point fails after reporting its steps: the error is one
  // line, the last.
  for (const auto &args : std::vector<std::vector<std::string>>{
           {"good.pcd", "out.pcd", "-outliers", "-outlier_fraction", "1", "-removed", "gone.pcd"},
           {"good.pcd", "out.pcd", "-outliers", "-outlier_fraction", "1", "-tv"}})
  {
    const ToolRun run = runTool (dir, args);
    const std::string what = describe (args, run);
    EXPECT_EQ (run.code, 1) << what;
    const auto error = run.err.find ("pcl_graph_denoise: error: ");
    ASSERT_NE (error, std::string::npos) << what;
    EXPECT_EQ (lines (run.err.substr (error)), 1u) << what;
    EXPECT_EQ (run.err.back (), '\n') << what;
    EXPECT_EQ (filesIn (dir), before) << "files left behind by: " << what;
  }

  // An existing output survives a failed run unchanged.
  write ("existing.pcd", "old content");
  const ToolRun run = runTool (dir, {"truncated.pcd", "existing.pcd"});
  EXPECT_EQ (run.code, 1);
  EXPECT_EQ (readFile (dir / "existing.pcd"), "old content");
}

TEST (Cli, InvalidCommandLinesExitWithTwoUnreadableInputWithOne)
{
  const fs::path dir = testFolder ();
  savePcd (dir / "good.pcd", sphereWithOutliers ());
  EXPECT_EQ (runTool (dir, {"good.pcd", "out.pcd", "-tv", "-gamma", "abc"}).code, 2);
  EXPECT_EQ (runTool (dir, {"good.pcd", "out.xyz"}).code, 2);
  EXPECT_EQ (runTool (dir, {"missing.pcd", "out.pcd"}).code, 1);
  const ToolRun run = runTool (dir, {"good.pcd", "out.pcd", "-tv", "-gamma", "-1"});
  EXPECT_NE (run.err.find ("-gamma"), std::string::npos) << run.err;
  EXPECT_NE (run.err.find (">= 0"), std::string::npos) << run.err;
}

// --- Sequences (-temporal) ----------------------------------------------------------------

/** Three frames of one noisy sphere (sizes differ), with every field. */
std::vector<PCLPointCloud2>
sphereFrames ()
{
  std::vector<PCLPointCloud2> frames;
  for (std::uint64_t t = 0; t < 3; ++t)
  {
    const auto xyz = pcl_graph_denoise::synthetic::noisySphere (1500 + 40 * t, 1.0, 0.02, 20 + t);
    frames.push_back (makeCloud (xyz, PCLPointField::FLOAT32, static_cast<std::uint32_t> (xyz.size ()), 1));
  }
  return frames;
}

TEST (Cli, TemporalStepWritesEveryFrameToTheFolderAsTheLibraryDoes)
{
  const fs::path dir = testFolder ();
  const auto frames = sphereFrames ();
  std::vector<std::string> names = {"f0.pcd", "f1.pcd", "f2.pcd"};
  for (std::size_t t = 0; t < 3; ++t)
    savePcd (dir / names[t], frames[t]);
  fs::create_directories (dir / "out");
  fs::create_directories (dir / "alone");
  // The frames as the library takes them.
  std::vector<pcl::PointCloud<pcl::PointXYZ>::Ptr> xyz;
  for (const auto &frame : frames)
  {
    xyz.emplace_back (new pcl::PointCloud<pcl::PointXYZ>);
    pcl::fromPCLPointCloud2 (frame, *xyz.back ());
  }
  for (const std::string &smoother : {"tikhonov", "tv"})
  {
    std::vector<std::string> args = names;
    args.insert (args.end (), {"out", "-temporal", "-smoother", smoother});
    const ToolRun run = runTool (dir, args);
    ASSERT_EQ (run.code, 0) << describe (args, run);
    EXPECT_NE (run.err.find ("frame 3/3"), std::string::npos) << run.err;
    // The library on the same frames.
    pcl_graph_denoise::GraphSequenceSmoothing<pcl::PointXYZ> sequence;
    if (smoother == "tv")
      sequence.setSmoother (std::make_shared<pcl_graph_denoise::GraphTVSmoothing<pcl::PointXYZ>> ());
    std::vector<pcl::PointCloud<pcl::PointXYZ>::Ptr> expected;
    ASSERT_TRUE (sequence.filter (xyz, expected));
    for (std::size_t t = 0; t < 3; ++t)
    {
      const PCLPointCloud2 output = load (dir / "out" / names[t]);
      const auto origin = expectFieldsKept (frames[t], output);
      ASSERT_EQ (origin.size (), size (frames[t]));
      std::size_t moved = 0;
      for (std::size_t i = 0; i < origin.size (); ++i)
      {
        EXPECT_EQ (coordinate (output, i, "x"), (*expected[t])[i].x) << "frame " << t << ", point " << i;
        EXPECT_EQ (coordinate (output, i, "z"), (*expected[t])[i].z) << "frame " << t << ", point " << i;
        moved += coordinate (output, i, "x") != coordinate (frames[t], i, "x");
      }
      EXPECT_GT (moved, origin.size () / 2);
    }
  }
  // An option of the sequence (motion compensation) and one of its smoother (the quadrics
  // over two rings only): the library's result with it, and not the default's; `report`,
  // when not empty, is what the tool must say about it.
  const auto optionReachesTheLibrary =
      [&] (const std::string &folder, const std::string &option, const std::string &report,
           const std::function<void (pcl_graph_denoise::GraphSequenceSmoothing<pcl::PointXYZ> &)> &set) {
        std::vector<std::string> args = names;
        fs::create_directories (dir / folder);
        args.insert (args.end (), {folder, "-temporal", option});
        const ToolRun run = runTool (dir, args);
        ASSERT_EQ (run.code, 0) << describe (args, run);
        if (!report.empty ())
          EXPECT_NE (run.err.find (report), std::string::npos) << run.err;
        pcl_graph_denoise::GraphSequenceSmoothing<pcl::PointXYZ> sequence;
        std::vector<pcl::PointCloud<pcl::PointXYZ>::Ptr> expected, plain;
        ASSERT_TRUE (sequence.filter (xyz, plain));
        set (sequence);
        ASSERT_TRUE (sequence.filter (xyz, expected));
        for (std::size_t t = 0; t < 3; ++t)
        {
          const PCLPointCloud2 output = load (dir / folder / names[t]);
          ASSERT_EQ (size (output), expected[t]->size ());
          std::size_t differ = 0;
          for (std::size_t i = 0; i < size (output); ++i)
          {
            EXPECT_EQ (coordinate (output, i, "x"), (*expected[t])[i].x) << option << ", frame " << t << ", point " << i;
            differ += coordinate (output, i, "x") != (*plain[t])[i].x;
          }
          EXPECT_GT (differ, 0u) << option << ", frame " << t;
        }
      };
  optionReachesTheLibrary ("moved", "motion_compensation=1", "motion compensation on",
                           [] (auto &sequence) { sequence.setMotionCompensation (true); });
  optionReachesTheLibrary ("two_rings", "adaptive_support=0", "", [] (auto &sequence) {
    auto smoother = std::make_shared<pcl_graph_denoise::GraphTikhonovSmoothing<pcl::PointXYZ>> ();
    smoother->setAdaptiveSupport (false);
    sequence.setSmoother (smoother);
  });
  // k2 = 0: each frame is the static filter's result (-tikhonov on the file alone).
  std::vector<std::string> args = names;
  args.insert (args.end (), {"alone", "-temporal", "k2=0"});
  ASSERT_EQ (runTool (dir, args).code, 0);
  for (std::size_t t = 0; t < 3; ++t)
  {
    const std::vector<std::string> single = {names[t], "single.pcd", "-tikhonov"};
    ASSERT_EQ (runTool (dir, single).code, 0);
    EXPECT_EQ (readFile (dir / "single.pcd"), readFile (dir / "alone" / names[t])) << "frame " << t;
  }
}

TEST (Cli, GammaRiskChoosesAsTheLibraryDoes)
{
  const fs::path dir = testFolder ();
  const PCLPointCloud2 input = sphereFrames ()[0];
  savePcd (dir / "in.pcd", input);
  pcl::PointCloud<pcl::PointXYZ>::Ptr xyz (new pcl::PointCloud<pcl::PointXYZ>);
  pcl::fromPCLPointCloud2 (input, *xyz);
  pcl_graph_denoise::GraphTikhonovSmoothing<pcl::PointXYZ> filter;
  filter.setGammaSelection (pcl_graph_denoise::GammaSelection::RISK_ESTIMATE);
  filter.setInputCloud (xyz);
  pcl::PointCloud<pcl::PointXYZ> expected;
  filter.filter (expected);
  for (const std::vector<std::string> &chain :
       {std::vector<std::string>{"-tikhonov", "-gamma", "risk"}, {"-tikhonov", "gamma=risk"}})
  {
    std::vector<std::string> args = {"in.pcd", "out.pcd"};
    args.insert (args.end (), chain.begin (), chain.end ());
    const ToolRun run = runTool (dir, args);
    ASSERT_EQ (run.code, 0) << describe (args, run);
    EXPECT_NE (run.err.find ("lowest estimated risk"), std::string::npos) << run.err;
    const PCLPointCloud2 output = load (dir / "out.pcd");
    ASSERT_EQ (size (output), expected.size ());
    for (std::size_t i = 0; i < expected.size (); ++i)
      ASSERT_EQ (coordinate (output, i, "y"), expected[i].y) << "point " << i;
  }
  // The rule's gamma is another: the choice made the difference.
  filter.setGammaSelection (pcl_graph_denoise::GammaSelection::RULE);
  const double chosen = filter.getUsedGamma ();
  filter.filter (expected);
  EXPECT_NE (filter.getUsedGamma (), chosen);
  const ToolRun run = runTool (dir, {"in.pcd", "out.pcd", "-tikhonov", "-gamma", "auto"});
  ASSERT_EQ (run.code, 0);
  EXPECT_NE (run.err.find ("(derived, estimated noise"), std::string::npos) << run.err;
  EXPECT_EQ (runTool (dir, {"in.pcd", "out.pcd", "-tikhonov", "-gamma", "risky"}).code, 2);
}

/** Runs the tool on dir/in.pcd (which holds xyz) with args and checks that its y
 *  coordinates are the library filter's on xyz, point by point; returns them (empty on a
 *  failure, which it reports). */
std::vector<float>
toolMatchesLibrary (const fs::path &dir, const std::vector<std::string> &args,
                    pcl_graph_denoise::GraphSmoothing<pcl::PointXYZ> &filter,
                    const pcl::PointCloud<pcl::PointXYZ>::Ptr &xyz)
{
  filter.setInputCloud (xyz);
  pcl::PointCloud<pcl::PointXYZ> expected;
  filter.filter (expected);
  const ToolRun run = runTool (dir, args);
  if (run.code != 0)
  {
    ADD_FAILURE () << describe (args, run);
    return {};
  }
  const PCLPointCloud2 output = load (dir / "out.pcd");
  if (size (output) != expected.size ())
  {
    ADD_FAILURE () << "size " << size (output) << " against " << expected.size ();
    return {};
  }
  std::vector<float> y;
  for (std::size_t i = 0; i < expected.size (); ++i)
  {
    if (coordinate (output, i, "y") != expected[i].y)
    {
      ADD_FAILURE () << describe (args, run) << ": point " << i << " differs";
      return {};
    }
    y.push_back (expected[i].y);
  }
  return y;
}

TEST (Cli, LocalSurfaceReachesTheFilter)
{
  // Each value of -local_surface gives the library's result with that surface; no
  // value gives the library's default (the blended quadrics); the three differ.
  const fs::path dir = testFolder ();
  const PCLPointCloud2 input = sphereFrames ()[0];
  savePcd (dir / "in.pcd", input);
  pcl::PointCloud<pcl::PointXYZ>::Ptr xyz (new pcl::PointCloud<pcl::PointXYZ>);
  pcl::fromPCLPointCloud2 (input, *xyz);
  const std::vector<std::pair<std::string, pcl_graph_denoise::LocalSurface>> surfaces = {
      {"", pcl_graph_denoise::LocalSurface::BLENDED_QUADRICS},
      {"plane", pcl_graph_denoise::LocalSurface::PLANE},
      {"quadric", pcl_graph_denoise::LocalSurface::QUADRIC},
      {"blended", pcl_graph_denoise::LocalSurface::BLENDED_QUADRICS}};
  std::map<std::string, std::vector<float>> y;  // the library's results
  for (const auto &[value, surface] : surfaces)
  {
    pcl_graph_denoise::GraphTVSmoothing<pcl::PointXYZ> filter;
    if (!value.empty ())
      filter.setLocalSurface (surface);
    std::vector<std::string> args = {"in.pcd", "out.pcd", "-tv"};
    if (!value.empty ())
      args.insert (args.end (), {"-local_surface", value});
    y[value] = toolMatchesLibrary (dir, args, filter, xyz);
    ASSERT_FALSE (y[value].empty ());
  }
  EXPECT_EQ (y[""], y["blended"]);
  EXPECT_NE (y["plane"], y["blended"]);
  EXPECT_NE (y["quadric"], y["blended"]);
  EXPECT_NE (y["plane"], y["quadric"]);
  const ToolRun help = runTool (dir, {"-h"});
  EXPECT_NE (help.out.find ("-local_surface plane|quadric|blended"), std::string::npos) << help.out;
  EXPECT_NE (help.out.find ("(default: blended)"), std::string::npos) << help.out;
}

/** The tool's results (y coordinates) on the first sphere frame with `step` and each of
 *  `values` of `option` ("": the option left out), each checked against the library's
 *  Filter set up by `configure` for that value. */
template <typename Filter>
std::map<std::string, std::vector<float>>
optionResults (const fs::path &dir, const std::string &step, const std::string &option,
               const std::vector<std::string> &values,
               const std::function<void (Filter &, const std::string &)> &configure)
{
  const PCLPointCloud2 input = sphereFrames ()[0];
  savePcd (dir / "in.pcd", input);
  pcl::PointCloud<pcl::PointXYZ>::Ptr xyz (new pcl::PointCloud<pcl::PointXYZ>);
  pcl::fromPCLPointCloud2 (input, *xyz);
  std::map<std::string, std::vector<float>> y;
  for (const std::string &value : values)
  {
    Filter filter;
    configure (filter, value);
    std::vector<std::string> args = {"in.pcd", "out.pcd", step};
    if (!value.empty ())
      args.insert (args.end (), {option, value});
    y[value] = toolMatchesLibrary (dir, args, filter, xyz);
    EXPECT_FALSE (y[value].empty ()) << option << " " << value;
  }
  return y;
}

/** The help's lines of the option whose line starts with `usage`, up to the next option. */
std::string
helpOf (const fs::path &dir, const std::string &usage)
{
  const ToolRun help = runTool (dir, {"-h"});
  const std::size_t from = help.out.find ("  " + usage);
  if (from == std::string::npos)
    return "(not in the help: " + help.out + ")";
  const std::size_t to = help.out.find ("\n  -", from + 1);
  return help.out.substr (from, to - from);
}

TEST (Cli, AdaptiveSupportReachesTheFilter)
{
  // -adaptive_support 0 gives the library's result with setAdaptiveSupport (false), 1 and
  // no value its default (on); the two differ, and the help tells the default.
  const fs::path dir = testFolder ();
  auto y = optionResults<pcl_graph_denoise::GraphTikhonovSmoothing<pcl::PointXYZ>> (
      dir, "-tikhonov", "-adaptive_support", {"", "0", "1"}, [] (auto &filter, const std::string &value) {
        if (value == "0")
          filter.setAdaptiveSupport (false);
      });
  EXPECT_EQ (y[""], y["1"]);
  EXPECT_NE (y["1"], y["0"]);
  EXPECT_EQ (runTool (dir, {"in.pcd", "out.pcd", "-tikhonov", "-adaptive_support", "maybe"}).code, 2);
  const std::string help = helpOf (dir, "-adaptive_support 0|1");
  EXPECT_NE (help.find ("(default: 1)"), std::string::npos) << help;
}

TEST (Cli, DensityNormalizationReachesTheFilter)
{
  // -density_normalization 0 gives the library's result with setDensityNormalization
  // (false), 1 and no value its default (on); the two differ, for TV too, and the help
  // tells the default.
  const fs::path dir = testFolder ();
  const auto off = [] (auto &filter, const std::string &value) {
    if (value == "0")
      filter.setDensityNormalization (false);
  };
  auto y = optionResults<pcl_graph_denoise::GraphTikhonovSmoothing<pcl::PointXYZ>> (
      dir, "-tikhonov", "-density_normalization", {"", "0", "1"}, off);
  EXPECT_EQ (y[""], y["1"]);
  EXPECT_NE (y["1"], y["0"]);
  auto z = optionResults<pcl_graph_denoise::GraphTVSmoothing<pcl::PointXYZ>> (
      dir, "-tv", "-density_normalization", {"", "0"}, off);
  EXPECT_NE (z[""], z["0"]);
  EXPECT_EQ (runTool (dir, {"in.pcd", "out.pcd", "-tv", "-density_normalization", "2"}).code, 2);
  const std::string help = helpOf (dir, "-density_normalization 0|1");
  EXPECT_NE (help.find ("(default: 1)"), std::string::npos) << help;
}

TEST (Cli, PatchCoverReachesTheFilter)
{
  // -patch_cover N gives the library's result with setPatchCover (N); no value is the
  // default (3); 0 and 3 differ; a negative or fractional cover is refused; the help
  // tells the default.
  const fs::path dir = testFolder ();
  auto y = optionResults<pcl_graph_denoise::GraphTVSmoothing<pcl::PointXYZ>> (
      dir, "-tv", "-patch_cover", {"", "0", "3"}, [] (auto &filter, const std::string &value) {
        if (!value.empty ())
          filter.setPatchCover (std::stoi (value));
      });
  EXPECT_EQ (y[""], y["3"]);
  EXPECT_NE (y["3"], y["0"]);
  for (const std::string bad : {"-1", "1.5", "many"})
    EXPECT_EQ (runTool (dir, {"in.pcd", "out.pcd", "-tv", "-patch_cover", bad}).code, 2) << bad;
  const std::string help = helpOf (dir, "-patch_cover N");
  EXPECT_NE (help.find ("(default: 3)"), std::string::npos) << help;
}

TEST (Cli, SmoothingReportsEachPassGraphAsItIsBuilt)
{
  const fs::path dir = testFolder ();
  savePcd (dir / "in.pcd", sphereWithOutliers ());
  const std::vector<std::string> args = {"in.pcd", "out.pcd", "-tikhonov", "-graph_iterations", "2", "-tv"};
  const ToolRun run = runTool (dir, args);
  ASSERT_EQ (run.code, 0) << describe (args, run);
  // Two passes of -tikhonov, one of -tv, on the 2100 points of the file.
  std::size_t lines_seen = 0;
  for (std::size_t at = 0; (at = run.err.find ("graph of 2100 points", at)) != std::string::npos; ++at)
    ++lines_seen;
  EXPECT_EQ (lines_seen, 3u) << run.err;
  EXPECT_NE (run.err.find ("  pass 2: graph of 2100 points, "), std::string::npos) << run.err;
  // Before the step's summary, not after it.
  EXPECT_LT (run.err.find ("pass 1: graph"), run.err.find ("moved")) << run.err;
  std::vector<std::string> quiet = args;
  quiet.push_back ("-q");
  const ToolRun silent = runTool (dir, quiet);
  ASSERT_EQ (silent.code, 0);
  EXPECT_EQ (silent.err.find ("graph of"), std::string::npos) << silent.err;
}

TEST (Cli, TemporalCommandLinesAreChecked)
{
  const fs::path dir = testFolder ();
  const auto frames = sphereFrames ();
  savePcd (dir / "f0.pcd", frames[0]);
  savePcd (dir / "f1.pcd", frames[1]);
  fs::create_directories (dir / "out");
  fs::create_directories (dir / "sub");
  savePcd (dir / "sub" / "f0.pcd", frames[2]);
  const std::vector<std::pair<std::vector<std::string>, std::string>> bad = {
      {{"f0.pcd", "f1.pcd", "out", "-tv"}, "-temporal"},
      {{"f0.pcd", "f1.pcd", "-temporal"}, "output folder"},
      {{"f0.pcd", "f1.pcd", "missing", "-temporal"}, "does not exist"},
      {{"f0.pcd", "sub/f0.pcd", "out", "-temporal"}, "two inputs"},
      {{"f0.pcd", "f1.pcd", ".", "-temporal"}, "overwrite"},
      {{"f0.pcd", "f1.pcd", "out", "-outliers", "-temporal", "-removed", "gone.pcd"}, "-removed"},
      {{"f0.pcd", "f1.pcd", "out", "-temporal", "-k2", "-1"}, ">= 0"},
      {{"f0.pcd", "f1.pcd", "out", "-temporal", "-window", "1.5"}, "integer"},
      {{"f0.pcd", "f1.pcd", "out", "-temporal", "-smoother", "median"}, "tikhonov or tv"},
      {{"f0.pcd", "f1.pcd", "out", "-temporal", "-norm", "anisotropic"}, "does not apply"},
      {{"f0.pcd", "f1.pcd", "out", "-temporal", "smoother=tv,solver=cholmod"}, "does not apply"},
      {{"f0.pcd", "out.pcd", "-tv", "-k2", "3"}, "only to -temporal"},
      {{"f0.pcd", "out.pcd", "-tv", "-motion_compensation", "0"}, "only to -temporal"},
      {{"f0.pcd", "f1.pcd", "out", "-temporal", "-motion_compensation", "2"}, "0 or 1"},
  };
  for (const auto &[args, message] : bad)
  {
    const ToolRun run = runTool (dir, args);
    EXPECT_EQ (run.code, 2) << describe (args, run);
    EXPECT_NE (run.err.find (message), std::string::npos) << describe (args, run);
    EXPECT_EQ (lines (run.err), 1u) << describe (args, run);
    EXPECT_TRUE (filesIn (dir / "out").empty ()) << describe (args, run);
  }
  // Given before the steps, -solver goes to the Tikhonov steps and not to a TV -temporal.
  const std::vector<std::string> args = {"f0.pcd", "f1.pcd", "out", "-solver", "cg", "-temporal", "smoother=tv"};
  const ToolRun run = runTool (dir, args);
  EXPECT_EQ (run.code, 0) << describe (args, run);
  EXPECT_EQ (filesIn (dir / "out"), (std::set<std::string>{"f0.pcd", "f1.pcd"}));
  // A frame that fails (all points non-finite) names its file; nothing is written.
  fs::remove_all (dir / "out");
  fs::create_directories (dir / "out");
  PCLPointCloud2 nan_frame = frames[1];
  for (std::size_t i = 0; i < size (nan_frame); ++i)
    for (const char *c : {"x", "y", "z"})
    {
      const float nan = std::numeric_limits<float>::quiet_NaN ();
      std::memcpy (&nan_frame.data[i * nan_frame.point_step + field (nan_frame, c)->offset], &nan, 4);
    }
  savePcd (dir / "f1.pcd", nan_frame);
  const ToolRun failed = runTool (dir, {"f0.pcd", "f1.pcd", "out", "-temporal"});
  EXPECT_EQ (failed.code, 1) << failed.err;
  EXPECT_NE (failed.err.find ("f1.pcd"), std::string::npos) << failed.err;
  EXPECT_TRUE (filesIn (dir / "out").empty ());
}

/** A cloud in pieces (a sphere and a far lone point): the report says so, and the lone
 *  point comes out where it went in. */
TEST (Cli, GraphInPiecesIsReported)
{
  const fs::path dir = testFolder ();
  auto xyz = pcl_graph_denoise::synthetic::noisySphere (2000, 1.0, 0.01, 9);
  xyz.push_back (pcl::PointXYZ (-900.0f, 40.0f, 7.0f));
  savePcd (dir / "pieces.pcd", makeCloud (xyz, PCLPointField::FLOAT32, xyz.size (), 1));
  for (const char *step : {"-tikhonov", "-tv"})
  {
    const std::vector<std::string> args = {"pieces.pcd", "out.pcd", step};
    const ToolRun run = runTool (dir, args);
    ASSERT_EQ (run.code, 0) << describe (args, run);
    EXPECT_NE (run.err.find ("connected components"), std::string::npos) << run.err;
    EXPECT_NE (run.err.find ("1 isolated points not moved"), std::string::npos) << run.err;
    pcl::PointCloud<pcl::PointXYZ> out;
    ASSERT_EQ (pcl::io::loadPCDFile ((dir / "out.pcd").string (), out), 0);
    ASSERT_EQ (out.size (), xyz.size ());
    EXPECT_EQ (out.back ().x, -900.0f);
    EXPECT_EQ (out.back ().y, 40.0f);
    EXPECT_EQ (out.back ().z, 7.0f);
  }
  xyz.resize (xyz.size () - 1);
  savePcd (dir / "whole.pcd", makeCloud (xyz, PCLPointField::FLOAT32, xyz.size (), 1));
  const ToolRun whole = runTool (dir, {"whole.pcd", "out.pcd", "-tv"});
  ASSERT_EQ (whole.code, 0) << whole.err;
  EXPECT_EQ (whole.err.find ("connected components"), std::string::npos) << whole.err;
}

/** -memory_limit reaches every step: below the estimate, the step fails up front with
 *  one line naming the limit and no output; a generous limit changes nothing. */
TEST (Cli, MemoryLimitRefusesACloudUpFront)
{
  const fs::path dir = testFolder ();
  savePcd (dir / "good.pcd", sphereWithOutliers ());
  const std::set<std::string> before = filesIn (dir);
  for (const auto &args : std::vector<std::vector<std::string>>{
           {"good.pcd", "out.pcd", "-outliers", "-memory_limit", "0.1"},
           {"good.pcd", "out.pcd", "-tikhonov", "-memory_limit", "0.1"},
           {"good.pcd", "out.pcd", "-tv", "-memory_limit", "0.1"}})
  {
    const ToolRun run = runTool (dir, args);
    const std::string what = describe (args, run);
    EXPECT_EQ (run.code, 1) << what;
    const auto error = run.err.find ("pcl_graph_denoise: error: ");
    ASSERT_NE (error, std::string::npos) << what;
    EXPECT_EQ (lines (run.err.substr (error)), 1u) << what;
    EXPECT_NE (run.err.find ("memory limit"), std::string::npos) << what;
    EXPECT_EQ (filesIn (dir), before) << "files left behind by: " << what;
  }
  const ToolRun limited = runTool (dir, {"good.pcd", "limited.pcd", "-tv", "-memory_limit", "100000"});
  const ToolRun free = runTool (dir, {"good.pcd", "free.pcd", "-tv"});
  ASSERT_EQ (limited.code, 0) << limited.err;
  ASSERT_EQ (free.code, 0) << free.err;
  EXPECT_EQ (readFile (dir / "limited.pcd"), readFile (dir / "free.pcd"));
  EXPECT_EQ (runTool (dir, {"good.pcd", "out.pcd", "-tv", "-memory_limit", "-1"}).code, 2);
}

/** The bad-input matrix of docs/reliability.md through the tool: degenerate clouds,
 *  extreme coordinates and extreme parameters either give an output of finite points
 *  (exit 0) or a one-line error (exit 1) and no file, never a crash or a hang. */
TEST (Cli, DegenerateCloudsAndExtremeParameters)
{
  const fs::path dir = testFolder ();
  const auto cloud = [] (const std::vector<std::array<float, 3>> &points) {
    pcl::PointCloud<pcl::PointXYZ> xyz;
    for (const auto &p : points)
      xyz.push_back (pcl::PointXYZ (p[0], p[1], p[2]));
    return makeCloud (xyz, PCLPointField::FLOAT32, static_cast<std::uint32_t> (xyz.size ()), 1);
  };
  const auto fromSynthetic = [] (pcl::PointCloud<pcl::PointXYZ> xyz) {
    return makeCloud (xyz, PCLPointField::FLOAT32, static_cast<std::uint32_t> (xyz.size ()), 1);
  };
  std::vector<std::array<float, 3>> line, grid, same (50, {4.0f, 5.0f, 6.0f});
  for (int i = 0; i < 100; ++i)
    line.push_back ({0.01f * i, 0.02f * i, -0.01f * i});
  for (int i = 0; i < 20; ++i)
    for (int j = 0; j < 20; ++j)
      grid.push_back ({0.01f * i, 0.01f * j, 0.0f});
  auto geo = pcl_graph_denoise::synthetic::noisyPlane (400, 0.005, 11);
  for (auto &p : geo)
    p.getVector3fMap () = p.getVector3fMap () * 1000.0f + Eigen::Vector3f (4.5e6f, 9.9e6f, 100.0f);
  auto micro = pcl_graph_denoise::synthetic::noisySphere (300, 1.0, 0.01, 3);
  for (auto &p : micro)
    p.getVector3fMap () *= 1e-6f;
  auto infinite = pcl_graph_denoise::synthetic::noisySphere (300, 1.0, 0.01, 4);
  for (std::size_t i = 0; i < infinite.size (); i += 30)
    infinite[i].data[i % 3] = (i % 60) ? std::numeric_limits<float>::infinity ()
                                       : -std::numeric_limits<float>::infinity ();
  auto far = pcl_graph_denoise::synthetic::noisySphere (300, 1.0, 0.01, 5);
  far[7].x = 1e20f;
  savePcd (dir / "one.pcd", cloud ({{1.5f, -2.0f, 3.25f}}));
  savePcd (dir / "two.pcd", cloud ({{1.0f, 2.0f, 3.0f}, {1.0f, 2.0f, 4.0f}}));
  savePcd (dir / "same.pcd", cloud (same));
  savePcd (dir / "line.pcd", cloud (line));
  savePcd (dir / "grid.pcd", cloud (grid));
  savePcd (dir / "geo.pcd", fromSynthetic (geo));
  savePcd (dir / "micro.pcd", fromSynthetic (micro));
  savePcd (dir / "infinite.pcd", fromSynthetic (infinite), false);  // "inf" as text
  savePcd (dir / "far.pcd", fromSynthetic (far));
  auto wide = pcl_graph_denoise::synthetic::noisySphere (300, 1.0, 0.01, 5);
  for (auto &p : wide)
    p.getVector3fMap () *= 1e30f;
  savePcd (dir / "wide.pcd", fromSynthetic (wide));
  savePcd (dir / "small.pcd", fromSynthetic (pcl_graph_denoise::synthetic::noisySphere (100, 1.0, 0.01, 6)));
  const std::set<std::string> before = filesIn (dir);

  /** Runs the tool; on success checks that every point of the output is finite and
   *  returns the output, else an empty cloud. */
  const auto succeeds = [&] (const std::vector<std::string> &args) {
    const ToolRun run = runTool (dir, args);
    EXPECT_EQ (run.code, 0) << describe (args, run);
    PCLPointCloud2 output;
    if (run.code != 0)
      return output;
    output = load (dir / args[1]);
    for (std::size_t i = 0; i < size (output); ++i)
      EXPECT_TRUE (finite (output, i)) << describe (args, run) << "\npoint " << i;
    fs::remove (dir / args[1]);
    return output;
  };
  const auto fails = [&] (const std::vector<std::string> &args, const std::string &text) {
    const ToolRun run = runTool (dir, args);
    const std::string what = describe (args, run);
    EXPECT_EQ (run.code, 1) << what;
    const auto error = run.err.find ("pcl_graph_denoise: error: ");
    ASSERT_NE (error, std::string::npos) << what;
    EXPECT_EQ (lines (run.err.substr (error)), 1u) << what;
    EXPECT_NE (run.err.find (text, error), std::string::npos) << what;
    EXPECT_EQ (filesIn (dir), before) << "files left behind by: " << what;
  };

  // Degenerate clouds through the default chain (-outliers -tv) and -tikhonov: every
  // point kept, and one point, identical points, a line and a plane are left in place.
  for (const std::string name : {"one", "two", "same", "line", "grid"})
    for (const std::vector<std::string> &chain : std::vector<std::vector<std::string>>{{}, {"-tikhonov"}})
    {
      std::vector<std::string> args = {name + ".pcd", "out.pcd"};
      args.insert (args.end (), chain.begin (), chain.end ());
      const PCLPointCloud2 input = load (dir / (name + ".pcd")), output = succeeds (args);
      ASSERT_EQ (size (output), size (input)) << name;
      for (std::size_t i = 0; i < size (output); ++i)
      {
        if (name == "two")  // the two points may move towards each other, on their line
          EXPECT_TRUE (coordinate (output, i, "x") == 1.0 && coordinate (output, i, "y") == 2.0);
        else if (name == "grid")
          EXPECT_EQ (coordinate (output, i, "z"), 0.0);
        else if (name != "line")
          for (const char *c : {"x", "y", "z"})
            EXPECT_EQ (coordinate (output, i, c), coordinate (input, i, c)) << name;
      }
    }
  // Extreme coordinates: geo-referenced (float steps of 1 m) and micrometres give finite
  // results of the right size; +-Inf points are removed by -outliers and passed through
  // by -tv; a garbage coordinate (1e20) is an outlier to -outliers and stays where it is
  // with -tikhonov; a cloud spanning more than 1e18 as a whole is refused.
  EXPECT_GT (size (succeeds ({"geo.pcd", "out.pcd"})), 390u);
  EXPECT_EQ (size (succeeds ({"micro.pcd", "out.pcd", "-tikhonov"})), micro.size ());
  EXPECT_GT (size (succeeds ({"infinite.pcd", "out.pcd"})), 280u);
  {
    const std::vector<std::string> args = {"infinite.pcd", "out.pcd", "-tv"};
    ASSERT_EQ (runTool (dir, args).code, 0);
    const PCLPointCloud2 output = load (dir / "out.pcd");
    ASSERT_EQ (size (output), infinite.size ());
    for (std::size_t i = 0; i < infinite.size (); ++i)
      EXPECT_EQ (finite (output, i), i % 30 != 0) << i;
    fs::remove (dir / "out.pcd");
  }
  {
    const PCLPointCloud2 cleaned = succeeds ({"far.pcd", "out.pcd", "-outliers"});
    EXPECT_GT (size (cleaned), 280u);
    for (std::size_t i = 0; i < size (cleaned); ++i)
      ASSERT_LT (std::abs (coordinate (cleaned, i, "x")), 10.0) << i;
    const PCLPointCloud2 smoothed = succeeds ({"far.pcd", "out.pcd", "-tikhonov"});
    ASSERT_EQ (size (smoothed), far.size ());
    EXPECT_EQ (coordinate (smoothed, 7, "x"), 1e20f);
  }
  fails ({"wide.pcd", "out.pcd"}, "the points span");
  fails ({"wide.pcd", "out.pcd", "-tikhonov"}, "the points span");

  // Zero and huge parameters: a result, or a one-line error naming the problem.
  EXPECT_EQ (size (succeeds ({"small.pcd", "out.pcd", "-outliers", "-outlier_fraction", "0"})), 100u);
  EXPECT_EQ (size (succeeds ({"small.pcd", "out.pcd", "-outliers", "radius=1e300,sigma=1e300"})), 100u);
  EXPECT_EQ (size (succeeds ({"small.pcd", "out.pcd", "-tv", "-k", "2147483647"})), 100u);
  EXPECT_EQ (size (succeeds ({"small.pcd", "out.pcd", "-tv", "-max_iterations", "2147483647"})), 100u);
  EXPECT_EQ (size (succeeds ({"small.pcd", "out.pcd", "-tv", "-sigma", "1e-300"})), 100u);
  EXPECT_EQ (size (succeeds ({"small.pcd", "out.pcd", "-threads", "1024", "-tikhonov", "-tv"})), 100u);
  EXPECT_EQ (size (succeeds ({"small.pcd", "out.pcd", "-tikhonov", "gamma=1e300,max_iterations=20"})), 100u);
  fails ({"small.pcd", "out.pcd", "-tv", "-gamma", "1e300"}, "too large for the total-variation solver");
  fails ({"small.pcd", "out.pcd", "-outliers", "-degree_threshold", "1e300"}, "no point is left");
}

/*
 * pcl_graph_denoise: graph-signal-processing point cloud denoising for PCL.
 * SPDX-License-Identifier: BSD-3-Clause
 *
 * The viewer: a cloud and its denoised result side by side in one PCLVisualizer window,
 * two viewports seen through one camera (moving one moves the other), each point of the
 * result coloured by how far it moved from the input, with a colour bar; or both clouds
 * coloured by depth. Interactive, or rendered once into a checked PNG (-png).
 *
 *   pcl_graph_denoise_viewer input.{pcd,ply} result.{pcd,ply} [options]
 *
 * See usageText() (or run with -h) for the options.
 */
#include "cloud_fields.h"
#include "cloud_io.h"
#include "stderr_capture.h"
#include "view_render.h"

#include <pcl/console/print.h>
#include <pcl/kdtree/kdtree_flann.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <exception>
#include <filesystem>
#include <limits>
#include <memory>
#include <new>
#include <stdexcept>
#include <string>
#include <vector>

using namespace pcl_graph_denoise::tools;

namespace {

using Cloud = pcl::PointCloud<pcl::PointXYZ>;

const char *const program = "pcl_graph_denoise_viewer";

/** Colour of the input's points when the result is coloured by displacement. */
constexpr std::uint8_t input_colour[3] = {90, 90, 90};

/** A command-line error: one line on stderr and exit code 2. */
struct UsageError : std::runtime_error
{
  using std::runtime_error::runtime_error;
};

enum class Colouring
{
  DISPLACEMENT,  ///< the result by how far each point moved from the input
  DEPTH          ///< both by the distance along the viewing direction
};

enum class Fit
{
  RESULT,
  INPUT,
  BOTH
};

struct ViewerOptions
{
  bool help = false;
  std::string input, result;
  std::string png;  ///< empty: interactive
  Colouring colouring = Colouring::DISPLACEMENT;
  Fit fit = Fit::RESULT;
  int width = 1600, height = 800;
  bool has_range = false;
  double lo = 0.0, hi = 0.0;
  double point_size = 0.0;  ///< 0: defaultPointSize()
  // PCL's default camera (pcl_viewer's): looking along +z from the origin, y down.
  Eigen::Vector3d direction{0.0, 0.0, 1.0};
  Eigen::Vector3d up{0.0, -1.0, 0.0};
};

std::string
usageText ()
{
  return std::string ("Usage: ") + program +
         " input.{pcd,ply} result.{pcd,ply} [options]\n"
         "\n"
         "Shows a cloud and its denoised result side by side, two views seen through one\n"
         "camera (moving one moves the other). Each point of the result is coloured by how\n"
         "far it moved from the input: from the input point of the same index when both\n"
         "clouds have the same size (the smoothing filters keep size and order), else from\n"
         "the nearest input point; a colour bar shows the scale. Points with a non-finite\n"
         "x, y or z are skipped. Needs an X server; without a display run it under\n"
         "  " +
         xvfb_hint +
         "\n"
         "\n"
         "Options:\n"
         "  -color displacement|depth  colour the result by displacement (the input is\n"
         "                             grey), or both clouds by depth: the distance along\n"
         "                             the viewing direction, z by default\n"
         "                             (default displacement)\n"
         "  -range LO HI               colour range (default: displacement 0 to its 98th\n"
         "                             percentile; depth its 1st to 99th percentile)\n"
         "  -view DX DY DZ UX UY UZ    viewing direction (camera towards the clouds) and\n"
         "                             up vector (default 0 0 1 0 -1 0, PCL's camera:\n"
         "                             along +z, y down)\n"
         "  -fit result|input|both     the camera frames this cloud (default result, so\n"
         "                             that far outliers of the input do not shrink it)\n"
         "  -point_size S              point size in pixels (default 2; 3 below 20000\n"
         "                             points, 4 below 2000)\n"
         "  -size W H                  window size in pixels (default 1600 800)\n"
         "  -png OUT.png               render once without an interactor, write OUT.png,\n"
         "                             read it back and keep it only if each view shows\n"
         "                             its points; prints the path and the fraction of\n"
         "                             non-background pixels of each view\n"
         "  -h, --help                 this text\n"
         "\n"
         "In the window the mouse rotates, zooms and pans both views; r resets the camera,\n"
         "q quits. Exit code 0 on success, 2 for an invalid command line, 1 for an\n"
         "unreadable input, no X display, or a picture that fails the check (no PNG is\n"
         "kept).\n";
}

/** Parses the command line; throws UsageError with a one-line message. */
ViewerOptions
parseViewerArguments (int argc, char **argv)
{
  ViewerOptions options;
  std::vector<std::string> files;
  int i = 1;
  // The n values after the option at i; moves i past them.
  const auto take = [&] (int n) {
    const std::string option = argv[i];
    if (i + n >= argc)
      throw UsageError (option + " needs " + std::to_string (n) + (n > 1 ? " values" : " value"));
    std::vector<const char *> values (argv + i + 1, argv + i + 1 + n);
    i += n;
    return values;
  };
  try
  {
    for (; i < argc; ++i)
    {
      const std::string arg = argv[i];
      if (arg.empty () || arg[0] != '-')
        files.push_back (arg);
      else if (arg == "-h" || arg == "--help")
        options.help = true;
      else if (arg == "-color")
      {
        const std::string name = take (1)[0];
        if (name != "displacement" && name != "depth")
          throw UsageError ("invalid value '" + printable (name, 40) +
                            "' for -color: expected displacement or depth");
        options.colouring = name == "depth" ? Colouring::DEPTH : Colouring::DISPLACEMENT;
      }
      else if (arg == "-fit")
      {
        const std::string name = take (1)[0];
        if (name != "result" && name != "input" && name != "both")
          throw UsageError ("invalid value '" + printable (name, 40) +
                            "' for -fit: expected result, input or both");
        options.fit = name == "input" ? Fit::INPUT : name == "both" ? Fit::BOTH : Fit::RESULT;
      }
      else if (arg == "-range")
      {
        const auto v = take (2);
        options.lo = parseFiniteNumber (arg, v[0]);
        options.hi = parseFiniteNumber (arg, v[1]);
        if (!(options.hi > options.lo))
          throw UsageError ("-range: LO must be smaller than HI");
        options.has_range = true;
      }
      else if (arg == "-view")
      {
        const auto v = take (6);
        for (int k = 0; k < 3; ++k)
        {
          options.direction[k] = parseFiniteNumber (arg, v[k]);
          options.up[k] = parseFiniteNumber (arg, v[3 + k]);
        }
        checkViewVectors (arg, options.direction, options.up);
      }
      else if (arg == "-point_size")
      {
        options.point_size = parseFiniteNumber (arg, take (1)[0]);
        if (!(options.point_size > 0.0 && options.point_size <= 50.0))
          throw UsageError ("-point_size: S must be in (0, 50]");
      }
      else if (arg == "-size")
      {
        const auto v = take (2);
        options.width = parsePixels (arg, v[0]);
        options.height = parsePixels (arg, v[1]);
      }
      else if (arg == "-png")
      {
        options.png = take (1)[0];
        if (!hasPngExtension (options.png))
          throw UsageError ("-png: the picture '" + printable (options.png, 80) + "' must end in .png");
      }
      else
        throw UsageError ("unknown option '" + printable (arg, 40) + "' (" + program + " -h for the usage)");
    }
  }
  catch (const std::invalid_argument &e)  // from the number parsers
  {
    throw UsageError (e.what ());
  }
  if (options.help)
    return options;
  if (files.size () != 2)
    throw UsageError ("expected an input and a result file, got " + std::to_string (files.size ()) + " (" +
                      program + " -h for the usage)");
  for (const auto &file : files)
    try
    {
      formatOf (file);
    }
    catch (const Error &e)
    {
      throw UsageError (e.what ());
    }
  options.input = files[0];
  options.result = files[1];
  if (!SideBySideViews::fits (2, options.width, options.height, true))
    throw UsageError ("-size: the window is too small for two views and a colour bar");
  return options;
}

/** The positions of .pcd or .ply files with any fields (x, y, z float or double), in
 *  each file's order, non-finite points included; double coordinates about one origin
 *  (setCommonOrigin), so that geo-referenced clouds keep their precision and stay
 *  comparable. */
std::vector<Cloud::Ptr>
loadPositions (const std::vector<std::string> &paths)
{
  std::vector<CloudFile> files;
  std::vector<XyzFields> fields;
  std::vector<const pcl::PCLPointCloud2 *> clouds;
  for (const std::string &path : paths)
  {
    files.push_back (loadCloud (path));
    fields.emplace_back (files.back ().cloud, path);
  }
  for (const CloudFile &file : files)
    clouds.push_back (&file.cloud);
  setCommonOrigin (fields, clouds);
  std::vector<Cloud::Ptr> out;
  for (std::size_t f = 0; f < files.size (); ++f)
    out.push_back (fields[f].extract (files[f].cloud));
  return out;
}

bool
isFinite (const pcl::PointXYZ &p)
{
  return std::isfinite (p.x) && std::isfinite (p.y) && std::isfinite (p.z);
}

/** How far each point of `result` lies from `input`: from the input point of the same
 *  index when the clouds have the same size and that point is finite, else from the
 *  nearest finite input point (kd-tree); NaN for a non-finite result point. */
std::vector<double>
displacements (const Cloud &input, const Cloud &result, std::size_t &by_index, std::size_t &by_nearest)
{
  const bool same_size = input.size () == result.size ();
  std::vector<double> moved (result.size (), std::numeric_limits<double>::quiet_NaN ());
  pcl::KdTreeFLANN<pcl::PointXYZ> tree;
  bool tree_built = false;
  by_index = by_nearest = 0;
  for (std::size_t i = 0; i < result.size (); ++i)
  {
    const auto &p = result[i];
    if (!isFinite (p))
      continue;
    if (same_size && isFinite (input[i]))
    {
      moved[i] = (p.getVector3fMap () - input[i].getVector3fMap ()).norm ();
      ++by_index;
      continue;
    }
    if (!tree_built)
    {
      auto finite = std::make_shared<Cloud> ();
      for (const auto &q : input)
        if (isFinite (q))
          finite->push_back (q);
      tree.setInputCloud (finite);
      tree_built = true;
    }
    pcl::Indices nearest (1);
    std::vector<float> squared (1);
    if (tree.nearestKSearch (p, 1, nearest, squared) == 1)
    {
      moved[i] = std::sqrt (static_cast<double> (squared[0]));
      ++by_nearest;
    }
  }
  return moved;
}

/** The finite points of `cloud` in one colour, and the scalars of those points. */
ColouredCloud::Ptr
finitePoints (const Cloud &cloud, const std::vector<double> &scalar, std::vector<double> &kept)
{
  auto out = std::make_shared<ColouredCloud> ();
  kept.clear ();
  for (std::size_t i = 0; i < cloud.size (); ++i)
    if (isFinite (cloud[i]))
    {
      pcl::PointXYZRGB q;
      q.getVector3fMap () = cloud[i].getVector3fMap ();
      q.r = input_colour[0];
      q.g = input_colour[1];
      q.b = input_colour[2];
      out->push_back (q);
      kept.push_back (i < scalar.size () ? scalar[i] : std::numeric_limits<double>::quiet_NaN ());
    }
  out->is_dense = true;
  return out;
}

/** The value at fraction q (0 to 1) of the sorted finite values; NaN without one. */
double
quantile (std::vector<double> values, double q)
{
  values.erase (std::remove_if (values.begin (), values.end (), [] (double v) { return !std::isfinite (v); }),
                values.end ());
  if (values.empty ())
    return std::numeric_limits<double>::quiet_NaN ();
  const auto k = static_cast<std::size_t> (std::floor (q * (values.size () - 1)));
  std::nth_element (values.begin (), values.begin () + k, values.end ());
  return values[k];
}

std::string
fileName (const std::string &path)
{
  return std::filesystem::path (path).filename ().string ();
}

int
run (const ViewerOptions &options)
{
  const bool headless = !options.png.empty ();
  if (headless)
    checkPngWritable (options.png);
  const std::vector<Cloud::Ptr> loaded = loadPositions ({options.input, options.result});
  const Cloud::Ptr input = loaded[0];
  const Cloud::Ptr result = loaded[1];
  const DisplayConnection display;  // fails early without one; outlives the window

  // Scalars on every point of each file, then the finite points with theirs.
  std::vector<double> input_scalar, result_scalar;
  std::string title;
  if (options.colouring == Colouring::DISPLACEMENT)
  {
    std::size_t by_index = 0, by_nearest = 0;
    result_scalar = displacements (*input, *result, by_index, by_nearest);
    title = by_nearest == 0 ? "displacement from the input point of the same index"
                            : by_index == 0 ? "distance to the nearest input point"
                                            : "displacement (same index, else nearest input point)";
    pcl::console::print_info (stderr, "%s: %zu result points compared by index, %zu with the nearest input "
                                      "point; moved: median %g, 98th percentile %g, max %g\n",
                               program, by_index, by_nearest, quantile (result_scalar, 0.5),
                               quantile (result_scalar, 0.98), quantile (result_scalar, 1.0));
  }
  else
  {
    const auto depth = [&] (const Cloud &cloud) {
      std::vector<double> d (cloud.size ());
      for (std::size_t i = 0; i < cloud.size (); ++i)
        d[i] = cloud[i].getVector3fMap ().cast<double> ().dot (options.direction);
      return d;
    };
    input_scalar = depth (*input);
    result_scalar = depth (*result);
    title = options.direction == Eigen::Vector3d::UnitZ () ? "depth (z)" : "depth along the viewing direction";
  }
  std::vector<double> input_kept, result_kept;
  const ColouredCloud::Ptr input_points = finitePoints (*input, input_scalar, input_kept);
  const ColouredCloud::Ptr result_points = finitePoints (*result, result_scalar, result_kept);
  if (input_points->empty ())
    throw Error (options.input + ": no point has a finite x, y, z");
  if (result_points->empty ())
    throw Error (options.result + ": no point has a finite x, y, z");

  double lo = options.lo, hi = options.hi;
  if (!options.has_range && options.colouring == Colouring::DISPLACEMENT)
    defaultScalarRange (result_kept, lo, hi);
  else if (!options.has_range)
  {
    std::vector<double> both (input_kept);
    both.insert (both.end (), result_kept.begin (), result_kept.end ());
    lo = quantile (both, 0.01);
    hi = quantile (both, 0.99);
    if (!(hi > lo))
      defaultScalarRange (both, lo, hi);
  }
  const auto table = makeViridisTable (lo, hi);
  colourByScalar (*result_points, result_kept, *table);
  if (options.colouring == Colouring::DEPTH)
    colourByScalar (*input_points, input_kept, *table);

  SideBySideViews window (std::string (program) + ": " + fileName (options.input) + " | " +
                              fileName (options.result),
                          2, options.width, options.height, true, !headless);
  const double point_size = options.point_size > 0.0
                                ? options.point_size
                                : defaultPointSize (std::max (input_points->size (), result_points->size ()));
  window.addCloud (0, input_points,
                   "input: " + fileName (options.input) + " (" + std::to_string (input_points->size ()) + " points)",
                   point_size);
  window.addCloud (1, result_points,
                   "result: " + fileName (options.result) + " (" + std::to_string (result_points->size ()) +
                       " points)",
                   point_size);
  window.addColourBar (table, title);
  std::vector<ColouredCloud::ConstPtr> fitted;
  if (options.fit != Fit::RESULT)
    fitted.push_back (input_points);
  if (options.fit != Fit::INPUT)
    fitted.push_back (result_points);
  const double radius = window.fitCamera (fitted, options.direction, options.up);

  if (!headless)
  {
    window.spin ();
    return 0;
  }
  const auto coverage = window.writeCheckedPng (options.png, {options.input, options.result}, radius);
  std::printf ("%s\n",
               describeCoverage (options.png, window.width (), window.height (), coverage, {"input", "result"})
                   .c_str ());
  return 0;
}

int
fail (const std::string &message, int code)
{
  pcl::console::print_error (stderr, "%s: error: %s\n", program, printable (message, 400).c_str ());
  return code;
}

}  // namespace

int
main (int argc, char **argv)
{
  try
  {
    const ViewerOptions options = parseViewerArguments (argc, argv);
    if (!options.help)
      return run (options);
    std::fputs (usageText ().c_str (), stdout);
    return 0;
  }
  catch (const UsageError &e)
  {
    return fail (e.what (), 2);
  }
  catch (const std::exception &e)  // unreadable input, no display, a failed picture
  {
    return fail (dynamic_cast<const std::bad_alloc *> (&e) ? "out of memory" : e.what (), 1);
  }
}

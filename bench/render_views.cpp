/*
 * pcl_graph_denoise: graph-signal-processing point cloud denoising for PCL.
 * SPDX-License-Identifier: BSD-3-Clause
 *
 * Pictures for the evaluation report: one to three point clouds side by side, one
 * viewport each in one PCLVisualizer window, all seen through the same camera, rendered
 * once without an interactor and written to a PNG. It needs an X server: on a machine
 * without a display run it under Xvfb.
 *
 *   render_views OUT.png [--size W H] [--range LO HI] [--view DX DY DZ UX UY UZ] [--fit N]
 *                [--point-size S] [--scalar-title TEXT]
 *                LABEL1 FILE1 [LABEL2 FILE2 [LABEL3 FILE3]]
 *
 *   xvfb-run -a -s "-screen 0 1920x1080x24" render_views cmp.png noisy in.pcd ours out.pcd
 *
 * FILE is a .pcd or .ply file. A cloud with a "distance" (else "intensity") field is
 * coloured by it with viridis, over one range for all views: --range, else 0 to the 98th
 * percentile of the values of all clouds (-a to a, a the 98th percentile of |value|, when
 * a value is negative); one colour bar under the views shows it. A cloud without such a
 * field keeps its rgb/rgba colours, else it is drawn in one colour. Points with a
 * non-finite coordinate are skipped; points with a non-finite scalar are drawn grey.
 * --view gives the viewing direction (from the camera towards the centre) and the up
 * vector, default -1 -1 -1 0 0 1 (a 3/4 view from above); the camera distance fits the
 * bounding sphere of all clouds (--fit N: of view N's cloud only, e.g. the cloud left
 * after outlier removal, so that far outliers do not shrink the picture). Defaults: size 800n x 800 for n views; point size 2,
 * or 3 when the largest cloud has fewer than 20000 points, 4 below 2000.
 *
 * The PNG is read back: each view must show at least min(0.5% of its area, a quarter of
 * the area its points can cover) pixels that differ from the white background, outside
 * its label. On success it prints the path, the size and those fractions. Exit code 0 on
 * success, 2 on a usage or input error (no PNG written), 1 if the rendering fails the
 * check (no PNG kept).
 *
 * The window, the colours, the camera and the checked PNG are tools/view_render.h's,
 * shared with the pcl_graph_denoise_viewer tool.
 */
#include "view_render.h"

#include <pcl/PCLPointCloud2.h>
#include <pcl/common/io.h>
#include <pcl/console/print.h>
#include <pcl/io/pcd_io.h>
#include <pcl/io/ply_io.h>
#include <pcl/point_cloud.h>
#include <pcl/point_types.h>

#include <Eigen/Core>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <limits>
#include <memory>
#include <set>
#include <stdexcept>
#include <string>
#include <vector>

using namespace pcl_graph_denoise::tools;

namespace {

const char *const usage_text =
    "usage: render_views OUT.png [--size W H] [--range LO HI] [--view DX DY DZ UX UY UZ] [--fit N]\n"
    "                    [--point-size S] [--scalar-title TEXT]\n"
    "                    LABEL1 FILE1 [LABEL2 FILE2 [LABEL3 FILE3]]\n"
    "\n"
    "Renders 1 to 3 point clouds (.pcd or .ply) side by side with one shared camera and\n"
    "writes OUT.png. Needs an X server; headless: xvfb-run -a -s \"-screen 0 1920x1080x24\".\n"
    "\n"
    "  --size W H           window size in pixels (default 800n x 800 for n clouds)\n"
    "  --range LO HI        colour range of the \"distance\"/\"intensity\" field (default 0 to\n"
    "                       its 98th percentile over all clouds, -a..a if a value is < 0)\n"
    "  --fit N              fit the camera to view N's cloud only (default: all clouds)\n"
    "  --view DX DY DZ UX UY UZ\n"
    "                       viewing direction (camera towards the centre) and up vector\n"
    "                       (default -1 -1 -1 0 0 1)\n"
    "  --point-size S       point size in pixels (default 2; 3 below 20000 points, 4\n"
    "                       below 2000)\n"
    "  --scalar-title TEXT  colour bar title (default the field name)\n"
    "  --                   ends the options (for a label starting with '-')\n"
    "  -h, --help           this text\n"
    "\n"
    "Colouring: by the \"distance\" (else \"intensity\") field with viridis and one colour bar;\n"
    "else by rgb/rgba; else one colour. Exit code 0 ok, 2 usage or input error, 1 the\n"
    "written picture failed the check that every view shows the cloud.\n";

/** A usage or input error: one line on stderr, exit code 2, nothing written. */
struct InputError : std::runtime_error
{
  using std::runtime_error::runtime_error;
};

constexpr std::uint8_t single_colour[3] = {49, 104, 142};  // the steel blue of viridis
constexpr int max_views = SideBySideViews::max_views;

struct Options
{
  std::string out;
  int width = 0, height = 0;  // 0: default
  bool has_range = false;
  double lo = 0.0, hi = 0.0;
  Eigen::Vector3d direction{-1.0, -1.0, -1.0};
  Eigen::Vector3d up{0.0, 0.0, 1.0};
  double point_size = 0.0;  // 0: default
  int fit = 0;              // 0: the camera fits all clouds; else the view (1-based) it fits
  bool has_title = false;
  std::string scalar_title;
  std::vector<std::pair<std::string, std::string>> views;  // label, file
};

struct View
{
  std::string label, file;
  std::string scalar_name;  // empty: not coloured by a scalar
  pcl::PointCloud<pcl::PointXYZRGB>::Ptr cloud{new pcl::PointCloud<pcl::PointXYZRGB>};
  std::vector<double> scalar;  // per point of cloud, when scalar_name is set
};

std::string
lower (std::string s)
{
  for (auto &c : s)
    c = static_cast<char> (std::tolower (static_cast<unsigned char> (c)));
  return s;
}

Options
parseArguments (int argc, char **argv)
{
  Options opt;
  std::vector<std::string> positional;
  bool options_done = false;
  for (int i = 1; i < argc; ++i)
  {
    const std::string arg = argv[i];
    const auto need = [&] (int n) {
      if (i + n >= argc)
        throw InputError (arg + " needs " + std::to_string (n) + " value" + (n > 1 ? "s" : ""));
    };
    if (options_done || arg.size () < 2 || arg[0] != '-' || std::isdigit (static_cast<unsigned char> (arg[1])) ||
        arg[1] == '.')
    {
      positional.push_back (arg);
      continue;
    }
    if (arg == "--")
      options_done = true;
    else if (arg == "-h" || arg == "--help")
    {
      std::fputs (usage_text, stdout);
      std::exit (0);
    }
    else if (arg == "--size")
    {
      need (2);
      opt.width = parsePixels (arg, argv[i + 1]);
      opt.height = parsePixels (arg, argv[i + 2]);
      i += 2;
    }
    else if (arg == "--range")
    {
      need (2);
      opt.lo = parseFiniteNumber (arg, argv[i + 1]);
      opt.hi = parseFiniteNumber (arg, argv[i + 2]);
      if (!(opt.hi > opt.lo))
        throw InputError ("--range: LO must be smaller than HI");
      opt.has_range = true;
      i += 2;
    }
    else if (arg == "--view")
    {
      need (6);
      for (int k = 0; k < 3; ++k)
      {
        opt.direction[k] = parseFiniteNumber (arg, argv[i + 1 + k]);
        opt.up[k] = parseFiniteNumber (arg, argv[i + 4 + k]);
      }
      checkViewVectors (arg, opt.direction, opt.up);
      i += 6;
    }
    else if (arg == "--fit")
    {
      need (1);
      const double view = parseFiniteNumber (arg, argv[i + 1]);
      if (!(view >= 1.0 && view <= 3.0 && view == std::floor (view)))
        throw InputError ("--fit: N must be the number of a view (1 to 3)");
      opt.fit = static_cast<int> (view);
      i += 1;
    }
    else if (arg == "--point-size")
    {
      need (1);
      opt.point_size = parseFiniteNumber (arg, argv[i + 1]);
      if (!(opt.point_size > 0.0 && opt.point_size <= 50.0))
        throw InputError ("--point-size: S must be in (0, 50]");
      i += 1;
    }
    else if (arg == "--scalar-title")
    {
      need (1);
      opt.scalar_title = argv[i + 1];
      opt.has_title = true;
      i += 1;
    }
    else
      throw InputError ("unknown option '" + arg + "' (render_views -h for the usage)");
  }
  opt.direction.normalize ();  // the defaults too
  opt.up.normalize ();
  if (positional.empty ())
    throw InputError ("missing OUT.png and clouds (render_views -h for the usage)");
  opt.out = positional[0];
  if (!hasPngExtension (opt.out))
    throw InputError ("the output '" + opt.out + "' must end in .png (render_views -h for the usage)");
  const std::size_t rest = positional.size () - 1;
  if (rest == 0 || rest % 2 != 0 || rest > 2 * max_views)
    throw InputError ("expected 1 to 3 LABEL FILE pairs after " + opt.out + ", got " + std::to_string (rest) +
                      " argument" + (rest == 1 ? "" : "s"));
  for (std::size_t i = 1; i < positional.size (); i += 2)
    opt.views.emplace_back (positional[i], positional[i + 1]);
  return opt;
}

// --- Reading any field of a PCLPointCloud2, whatever its type -------------------------

/** The field `name` if present with a known type, one value at least and inside the point. */
const pcl::PCLPointField *
findField (const pcl::PCLPointCloud2 &cloud, const std::string &name)
{
  for (const auto &f : cloud.fields)
    if (f.name == name)
    {
      const std::size_t size = pcl::getFieldSize (f.datatype);
      if (size == 0 || std::uint64_t (f.offset) + size > cloud.point_step)
        return nullptr;
      return &f;
    }
  return nullptr;
}

double
readValue (const std::uint8_t *p, std::uint8_t datatype)
{
  switch (datatype)
  {
#define RENDER_VIEWS_READ(ENUM, TYPE)                                                               \
  case pcl::PCLPointField::ENUM: {                                                                  \
    TYPE v;                                                                                         \
    std::memcpy (&v, p, sizeof (v));                                                                \
    return static_cast<double> (v);                                                                 \
  }
    RENDER_VIEWS_READ (INT8, std::int8_t)
    RENDER_VIEWS_READ (UINT8, std::uint8_t)
    RENDER_VIEWS_READ (INT16, std::int16_t)
    RENDER_VIEWS_READ (UINT16, std::uint16_t)
    RENDER_VIEWS_READ (INT32, std::int32_t)
    RENDER_VIEWS_READ (UINT32, std::uint32_t)
    RENDER_VIEWS_READ (INT64, std::int64_t)
    RENDER_VIEWS_READ (UINT64, std::uint64_t)
    RENDER_VIEWS_READ (FLOAT32, float)
    RENDER_VIEWS_READ (FLOAT64, double)
#undef RENDER_VIEWS_READ
  }
  return std::numeric_limits<double>::quiet_NaN ();
}

View
loadView (const std::string &label, const std::string &file)
{
  View view;
  view.label = label;
  view.file = file;
  std::error_code ec;
  if (!std::filesystem::exists (file, ec))
    throw InputError (file + ": no such file");
  if (!std::filesystem::is_regular_file (file, ec))
    throw InputError (file + ": not a regular file");
  const std::string ext = lower (std::filesystem::path (file).extension ().string ());
  pcl::PCLPointCloud2 blob;
  int rc = -1;
  try
  {
    if (ext == ".pcd")
    {
      // PCL 1.13 crashes reading a file without FIELDS (an empty file, another format):
      // look at the header first.
      pcl::PCDReader reader;
      Eigen::Vector4f origin;
      Eigen::Quaternionf orientation;
      int version = 0, data_type = 0;
      unsigned int data_index = 0;
      if (reader.readHeader (file, blob, origin, orientation, version, data_type, data_index) < 0 ||
          blob.fields.empty ())
        throw InputError (file + ": not a PCD file (no FIELDS in its header)");
      rc = reader.read (file, blob);
    }
    else if (ext == ".ply")
      rc = pcl::io::loadPLYFile (file, blob);
    else
      throw InputError (file + ": unknown format '" + ext + "' (expected .pcd or .ply)");
  }
  catch (const InputError &)
  {
    throw;
  }
  catch (const std::exception &e)
  {
    throw InputError (file + ": cannot read it: " + e.what ());
  }
  if (rc < 0)
    throw InputError (file + ": cannot read it as a " + ext.substr (1) + " file");

  const pcl::PCLPointField *fx = findField (blob, "x");
  const pcl::PCLPointField *fy = findField (blob, "y");
  const pcl::PCLPointField *fz = findField (blob, "z");
  if (!fx || !fy || !fz)
    throw InputError (file + ": no usable x, y and z fields");
  const pcl::PCLPointField *fs = findField (blob, "distance");
  if (!fs)
    fs = findField (blob, "intensity");
  const pcl::PCLPointField *fc = findField (blob, "rgb");
  if (!fc)
    fc = findField (blob, "rgba");
  if (fc && pcl::getFieldSize (fc->datatype) != 4)
    fc = nullptr;
  if (fs)
    view.scalar_name = fs->name;

  const std::uint64_t width = blob.width, height = blob.height;
  const std::uint64_t step = blob.point_step, row = blob.row_step;
  if (width * height > 0 && (step == 0 || row < width * step || blob.data.size () < (height - 1) * row + width * step))
    throw InputError (file + ": inconsistent point layout (point_step, row_step and data size)");

  auto &cloud = *view.cloud;
  cloud.reserve (width * height);
  for (std::uint64_t r = 0; r < height; ++r)
    for (std::uint64_t c = 0; c < width; ++c)
    {
      const std::uint8_t *p = blob.data.data () + r * row + c * step;
      const double x = readValue (p + fx->offset, fx->datatype);
      const double y = readValue (p + fy->offset, fy->datatype);
      const double z = readValue (p + fz->offset, fz->datatype);
      const float xf = static_cast<float> (x), yf = static_cast<float> (y), zf = static_cast<float> (z);
      if (!std::isfinite (xf) || !std::isfinite (yf) || !std::isfinite (zf))
        continue;
      pcl::PointXYZRGB q;
      q.x = xf;
      q.y = yf;
      q.z = zf;
      q.r = single_colour[0];
      q.g = single_colour[1];
      q.b = single_colour[2];
      if (fs)
        view.scalar.push_back (readValue (p + fs->offset, fs->datatype));
      else if (fc)
      {
        std::uint32_t packed;
        std::memcpy (&packed, p + fc->offset, 4);
        q.r = static_cast<std::uint8_t> ((packed >> 16) & 0xff);
        q.g = static_cast<std::uint8_t> ((packed >> 8) & 0xff);
        q.b = static_cast<std::uint8_t> (packed & 0xff);
      }
      cloud.push_back (q);
    }
  if (cloud.empty ())
    throw InputError (file + ": no point with finite coordinates");
  cloud.is_dense = true;
  return view;
}

// --- Colours --------------------------------------------------------------------------

/** Default range over the scalars of every view (see defaultScalarRange). */
void
defaultRange (const std::vector<View> &views, double &lo, double &hi)
{
  std::vector<double> values;
  for (const auto &v : views)
    values.insert (values.end (), v.scalar.begin (), v.scalar.end ());
  defaultScalarRange (std::move (values), lo, hi);
}

}  // namespace

int
main (int argc, char **argv)
{
  pcl::console::setVerbosityLevel (pcl::console::L_ALWAYS);  // our own one-line errors only
  Options opt;
  std::vector<View> views;
  std::unique_ptr<DisplayConnection> display;  // outlives the visualizer
  try
  {
    opt = parseArguments (argc, argv);
    for (const auto &[label, file] : opt.views)
      views.push_back (loadView (label, file));

    checkPngWritable (opt.out);  // before rendering
    display = std::make_unique<DisplayConnection> ();
  }
  catch (const std::exception &e)
  {
    std::fprintf (stderr, "render_views: error: %s\n", e.what ());
    return 2;
  }

  const int n = static_cast<int> (views.size ());
  try
  {
    // Colours.
    std::set<std::string> scalar_names;
    std::size_t largest = 0;
    for (const auto &v : views)
    {
      if (!v.scalar_name.empty ())
        scalar_names.insert (v.scalar_name);
      largest = std::max (largest, v.cloud->size ());
    }
    const bool by_scalar = !scalar_names.empty ();
    double lo = opt.lo, hi = opt.hi;
    vtkSmartPointer<vtkLookupTable> lut;
    if (by_scalar)
    {
      if (!opt.has_range)
        defaultRange (views, lo, hi);
      lut = makeViridisTable (lo, hi);
      for (auto &v : views)
        if (!v.scalar_name.empty ())
          colourByScalar (*v.cloud, v.scalar, *lut);
    }
    const double point_size = opt.point_size > 0.0 ? opt.point_size : defaultPointSize (largest);

    // Window: n views side by side over the whole height, less a strip for the colour bar.
    const int width = opt.width > 0 ? opt.width : 800 * n;
    const int height = opt.height > 0 ? opt.height : 800;
    if (!SideBySideViews::fits (n, width, height, by_scalar))
      throw InputError ("--size: the window is too small for " + std::to_string (n) + " views");
    if (opt.fit > n)
      throw InputError ("--fit: there is no view " + std::to_string (opt.fit));
    SideBySideViews window ("render_views", n, width, height, by_scalar, false);
    std::vector<ColouredCloud::ConstPtr> fitted;
    std::vector<std::string> files, labels;
    for (int i = 0; i < n; ++i)
    {
      window.addCloud (i, views[i].cloud, views[i].label, point_size);
      if (opt.fit == 0 || opt.fit == i + 1)
        fitted.push_back (views[i].cloud);
      files.push_back (views[i].file);
      labels.push_back (views[i].label);
    }
    if (by_scalar)
    {
      std::string title = opt.scalar_title;
      if (!opt.has_title)
        for (const auto &name : scalar_names)
          title += (title.empty () ? "" : " / ") + name;
      window.addColourBar (lut, title);
    }

    // One camera for every view, fitted to the bounding sphere of all clouds (or of the
    // one --fit names); render once, check the picture, then move it into place.
    const double radius = window.fitCamera (fitted, opt.direction, opt.up);
    const auto coverage = window.writeCheckedPng (opt.out, files, radius);
    std::printf ("%s\n", describeCoverage (opt.out, width, height, coverage, labels).c_str ());
    return 0;
  }
  catch (const InputError &e)
  {
    std::fprintf (stderr, "render_views: error: %s\n", e.what ());
    return 2;
  }
  catch (const std::exception &e)
  {
    std::fprintf (stderr, "render_views: error: %s\n", e.what ());
    return 1;
  }
}

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
 */
#include <pcl/PCLPointCloud2.h>
#include <pcl/common/io.h>
#include <pcl/console/print.h>
#include <pcl/io/pcd_io.h>
#include <pcl/io/ply_io.h>
#include <pcl/point_cloud.h>
#include <pcl/point_types.h>
#include <pcl/visualization/common/common.h>
#include <pcl/visualization/pcl_visualizer.h>
#include <pcl/visualization/point_cloud_color_handlers.h>

#include <vtkCamera.h>
#include <vtkImageData.h>
#include <vtkLookupTable.h>
#include <vtkPNGReader.h>
#include <vtkPNGWriter.h>
#include <vtkRenderWindow.h>
#include <vtkRenderer.h>
#include <vtkRendererCollection.h>
#include <vtkScalarBarActor.h>
#include <vtkSmartPointer.h>
#include <vtkTextProperty.h>
#include <vtkWindowToImageFilter.h>

#include <Eigen/Core>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <limits>
#include <memory>
#include <set>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

// Last: Xlib defines macros (Status, Success, None, ...) that clash with the headers above.
#include <X11/Xlib.h>

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

/** The rendered picture is unusable: exit code 1, nothing kept. */
struct RenderError : std::runtime_error
{
  using std::runtime_error::runtime_error;
};

constexpr std::uint8_t single_colour[3] = {49, 104, 142};  // the steel blue of viridis
constexpr std::uint8_t nan_colour[3] = {160, 160, 160};
constexpr double background[3] = {1.0, 1.0, 1.0};
constexpr int max_views = 3;

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

bool
endsWith (const std::string &s, const std::string &suffix)
{
  return s.size () >= suffix.size () && s.compare (s.size () - suffix.size (), suffix.size (), suffix) == 0;
}

double
parseNumber (const std::string &option, const char *text)
{
  errno = 0;
  char *end = nullptr;
  const double v = std::strtod (text, &end);
  if (end == text || *end != '\0' || errno == ERANGE || !std::isfinite (v))
    throw InputError (option + ": '" + text + "' is not a finite number");
  return v;
}

int
parsePixels (const std::string &option, const char *text)
{
  const double v = parseNumber (option, text);
  if (v != std::floor (v) || v < 100 || v > 8192)
    throw InputError (option + ": '" + text + "' is not a whole number of pixels in [100, 8192]");
  return static_cast<int> (v);
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
      opt.lo = parseNumber (arg, argv[i + 1]);
      opt.hi = parseNumber (arg, argv[i + 2]);
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
        opt.direction[k] = parseNumber (arg, argv[i + 1 + k]);
        opt.up[k] = parseNumber (arg, argv[i + 4 + k]);
      }
      if (!(opt.direction.norm () > 0.0) || !std::isfinite (opt.direction.norm ()))
        throw InputError ("--view: the viewing direction must be a non-zero vector");
      if (!(opt.up.norm () > 0.0) || !std::isfinite (opt.up.norm ()))
        throw InputError ("--view: the up vector must be a non-zero vector");
      if (opt.direction.normalized ().cross (opt.up.normalized ()).norm () < 1e-6)
        throw InputError ("--view: the up vector is parallel to the viewing direction");
      i += 6;
    }
    else if (arg == "--fit")
    {
      need (1);
      const double view = parseNumber (arg, argv[i + 1]);
      if (!(view >= 1.0 && view <= 3.0 && view == std::floor (view)))
        throw InputError ("--fit: N must be the number of a view (1 to 3)");
      opt.fit = static_cast<int> (view);
      i += 1;
    }
    else if (arg == "--point-size")
    {
      need (1);
      opt.point_size = parseNumber (arg, argv[i + 1]);
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
  if (!endsWith (lower (opt.out), ".png"))
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

/** Default range: 0 to the 98th percentile, or symmetric when a value is negative. */
void
defaultRange (const std::vector<View> &views, double &lo, double &hi)
{
  std::vector<double> values;
  bool negative = false;
  for (const auto &v : views)
    for (double s : v.scalar)
      if (std::isfinite (s))
      {
        values.push_back (s);
        negative = negative || s < 0.0;
      }
  if (values.empty ())
  {
    lo = 0.0;
    hi = 1.0;
    return;
  }
  const auto [min_it, max_it] = std::minmax_element (values.begin (), values.end ());
  const double vmin = *min_it, vmax = *max_it;
  if (negative)
    for (auto &s : values)
      s = std::abs (s);
  const std::size_t k = static_cast<std::size_t> (std::floor (0.98 * (values.size () - 1)));
  std::nth_element (values.begin (), values.begin () + k, values.end ());
  lo = negative ? -values[k] : 0.0;
  hi = values[k];
  if (!(hi > lo) || !std::isfinite (hi - lo))
  {
    lo = vmin;
    hi = vmax;
  }
  if (!(hi > lo) || !std::isfinite (hi - lo))
    hi = lo + (lo == 0.0 ? 1.0 : std::abs (lo));
}

/** PCL's viridis (else inverse jet) table, spread over [lo, hi]; out-of-range values clamp. */
vtkSmartPointer<vtkLookupTable>
makeLookupTable (double lo, double hi)
{
  vtkSmartPointer<vtkLookupTable> pcl_lut;
  if (!pcl::visualization::getColormapLUT (pcl::visualization::PCL_VISUALIZER_LUT_VIRIDIS, pcl_lut) &&
      !pcl::visualization::getColormapLUT (pcl::visualization::PCL_VISUALIZER_LUT_JET_INVERSE, pcl_lut))
    throw RenderError ("PCL provides neither the viridis nor the jet colour map");
  // Copy the colours into a table of our own: rebuilding PCL's after a range change
  // could replace its colours with the default hue ramp.
  const vtkIdType n = pcl_lut->GetNumberOfTableValues ();
  auto lut = vtkSmartPointer<vtkLookupTable>::New ();
  lut->SetTableRange (lo, hi);
  lut->SetNumberOfTableValues (n);
  lut->Build ();
  for (vtkIdType i = 0; i < n; ++i)
  {
    double rgba[4];
    pcl_lut->GetTableValue (i, rgba);
    lut->SetTableValue (i, rgba[0], rgba[1], rgba[2], 1.0);
  }
  lut->SetNanColor (nan_colour[0] / 255.0, nan_colour[1] / 255.0, nan_colour[2] / 255.0, 1.0);
  return lut;
}

void
applyScalarColours (View &view, vtkLookupTable &lut, double lo, double hi)
{
  const vtkIdType n = lut.GetNumberOfTableValues ();
  for (std::size_t i = 0; i < view.cloud->size (); ++i)
  {
    auto &q = (*view.cloud)[i];
    const double s = view.scalar[i];
    if (!std::isfinite (s))
    {
      q.r = nan_colour[0];
      q.g = nan_colour[1];
      q.b = nan_colour[2];
      continue;
    }
    const double t = std::clamp ((s - lo) / (hi - lo), 0.0, 1.0);
    const vtkIdType k = std::min<vtkIdType> (n - 1, static_cast<vtkIdType> (t * n));
    double rgba[4];
    lut.GetTableValue (k, rgba);
    q.r = static_cast<std::uint8_t> (std::lround (rgba[0] * 255.0));
    q.g = static_cast<std::uint8_t> (std::lround (rgba[1] * 255.0));
    q.b = static_cast<std::uint8_t> (std::lround (rgba[2] * 255.0));
  }
}

// --- Rendering and the check ----------------------------------------------------------

/** A connection to the X server, held while VTK opens its own. */
class DisplayConnection
{
public:
  DisplayConnection ()
  {
    const char *display = std::getenv ("DISPLAY");
    if (!display || !*display)
      throw InputError ("no X display (DISPLAY is not set); run under xvfb-run -a -s \"-screen 0 1920x1080x24\"");
    // VTK aborts the process when it cannot connect, so connect first. An X server
    // started without -noreset (xvfb-run's default) resets when its last client leaves
    // and refuses connections meanwhile: retry for a while, then keep this connection
    // open so that the server cannot reset before VTK has connected.
    for (int attempt = 0; attempt < 20 && !connection_; ++attempt)
    {
      if (attempt > 0)
        std::this_thread::sleep_for (std::chrono::milliseconds (100));
      connection_ = XOpenDisplay (nullptr);
    }
    if (!connection_)
      throw InputError (std::string ("cannot open the X display '") + display + "'");
  }
  ~DisplayConnection () { XCloseDisplay (connection_); }
  DisplayConnection (const DisplayConnection &) = delete;
  DisplayConnection &operator= (const DisplayConnection &) = delete;

private:
  ::Display *connection_ = nullptr;
};

vtkRenderer *
rendererOf (pcl::visualization::PCLVisualizer &viz, int viewport)
{
  return vtkRenderer::SafeDownCast (viz.getRendererCollection ()->GetItemAsObject (viewport));
}

struct Coverage
{
  double fraction;
  std::size_t pixels, required;
};

}  // namespace

int
main (int argc, char **argv)
{
  pcl::console::setVerbosityLevel (pcl::console::L_ALWAYS);  // our own one-line errors only
  Options opt;
  std::vector<View> views;
  std::string tmp;
  std::unique_ptr<DisplayConnection> display;  // outlives the visualizer
  try
  {
    opt = parseArguments (argc, argv);
    for (const auto &[label, file] : opt.views)
      views.push_back (loadView (label, file));

    // Fail before rendering when the output cannot be written.
    tmp = opt.out + ".partial.png";
    if (std::FILE *f = std::fopen (tmp.c_str (), "wb"))
    {
      std::fclose (f);
      std::remove (tmp.c_str ());
    }
    else
      throw InputError ("cannot write " + opt.out + ": " + std::strerror (errno));
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
      lut = makeLookupTable (lo, hi);
      for (auto &v : views)
        if (!v.scalar_name.empty ())
          applyScalarColours (v, *lut, lo, hi);
    }
    const double point_size = opt.point_size > 0.0 ? opt.point_size : largest < 2000 ? 4.0 : largest < 20000 ? 3.0 : 2.0;

    // Window: n views side by side over the whole height, less a strip for the colour bar.
    const int width = opt.width > 0 ? opt.width : 800 * n;
    const int height = opt.height > 0 ? opt.height : 800;
    const int strip = by_scalar ? std::clamp (static_cast<int> (std::lround (0.1 * height)), 50, 120) : 0;
    if (height - strip < 50 || width / n < 50)
      throw InputError ("--size: the window is too small for " + std::to_string (n) + " views");
    const double strip_top = static_cast<double> (strip) / height;
    const int font = std::clamp (static_cast<int> (std::lround (0.03 * height)), 12, 40);

    pcl::visualization::PCLVisualizer viz ("render_views", false);
    viz.getRenderWindow ()->SetOffScreenRendering (1);
    viz.setSize (width, height);
    viz.setShowFPS (false);
    std::vector<int> viewports (n, 0);
    for (int i = 0; i < n; ++i)
      viz.createViewPort (static_cast<double> (i) / n, strip_top, static_cast<double> (i + 1) / n, 1.0,
                          viewports[i]);
    int bar_viewport = 0;
    if (by_scalar)
      viz.createViewPort (0.0, 0.0, 1.0, strip_top, bar_viewport);
    viz.setBackgroundColor (background[0], background[1], background[2]);  // every renderer

    for (int i = 0; i < n; ++i)
    {
      const std::string id = "cloud" + std::to_string (i);
      pcl::visualization::PointCloudColorHandlerRGBField<pcl::PointXYZRGB> colours (views[i].cloud);
      if (!viz.addPointCloud<pcl::PointXYZRGB> (views[i].cloud, colours, id, viewports[i]))
        throw RenderError ("PCLVisualizer refused the cloud of " + views[i].file);
      viz.setPointCloudRenderingProperties (pcl::visualization::PCL_VISUALIZER_POINT_SIZE, point_size, id);
      if (!views[i].label.empty ())
        viz.addText (views[i].label, 10, height - strip - font - 10, font, 0.1, 0.1, 0.1,
                     "label" + std::to_string (i), viewports[i]);
    }

    if (by_scalar)
    {
      std::string title = opt.scalar_title;
      if (!opt.has_title)
        for (const auto &name : scalar_names)
          title += (title.empty () ? "" : " / ") + name;
      auto bar = vtkSmartPointer<vtkScalarBarActor>::New ();
      bar->SetLookupTable (lut);
      bar->SetOrientationToHorizontal ();
      bar->SetTitle (title.c_str ());
      bar->SetNumberOfLabels (width >= 1200 ? 5 : 3);  // room for "-0.0001234"-wide labels
      bar->SetLabelFormat ("%.4g");
      bar->SetPosition (0.25, 0.04);
      bar->SetWidth (0.5);
      bar->SetHeight (0.92);
      bar->SetTextPositionToPrecedeScalarBar ();
      for (vtkTextProperty *text : {bar->GetTitleTextProperty (), bar->GetLabelTextProperty ()})
      {
        text->SetColor (0.1, 0.1, 0.1);
        text->ShadowOff ();
        text->ItalicOff ();
        text->BoldOff ();
      }
      rendererOf (viz, bar_viewport)->AddActor2D (bar);
    }

    // One camera for every view, fitted to the bounding sphere of all clouds (or of the
    // one --fit names).
    if (opt.fit > n)
      throw InputError ("--fit: there is no view " + std::to_string (opt.fit));
    std::vector<const View *> fitted;
    for (int i = 0; i < n; ++i)
      if (opt.fit == 0 || opt.fit == i + 1)
        fitted.push_back (&views[i]);
    Eigen::Vector3d min_pt = Eigen::Vector3d::Constant (std::numeric_limits<double>::max ());
    Eigen::Vector3d max_pt = -min_pt;
    for (const View *v : fitted)
      for (const auto &p : *v->cloud)
      {
        const Eigen::Vector3d q = p.getVector3fMap ().cast<double> ();
        min_pt = min_pt.cwiseMin (q);
        max_pt = max_pt.cwiseMax (q);
      }
    const Eigen::Vector3d centre = 0.5 * (min_pt + max_pt);
    double radius = 0.0;
    for (const View *v : fitted)
      for (const auto &p : *v->cloud)
        radius = std::max (radius, (p.getVector3fMap ().cast<double> () - centre).norm ());
    radius = std::max (radius, 1e-3 * std::max (1.0, centre.cwiseAbs ().maxCoeff ()));
    const double view_angle = 30.0;  // vertical, degrees
    const double aspect = (static_cast<double> (width) / n) / (height - strip);
    const double half_v = 0.5 * view_angle * M_PI / 180.0;
    const double half = std::min (half_v, std::atan (std::tan (half_v) * aspect));
    const double distance = 1.05 * radius / std::sin (half);
    const Eigen::Vector3d eye = centre - distance * opt.direction;
    vtkCamera *camera = rendererOf (viz, viewports[0])->GetActiveCamera ();
    camera->SetViewAngle (view_angle);
    camera->SetFocalPoint (centre.x (), centre.y (), centre.z ());
    camera->SetPosition (eye.x (), eye.y (), eye.z ());
    camera->SetViewUp (opt.up.x (), opt.up.y (), opt.up.z ());
    camera->OrthogonalizeViewUp ();
    camera->SetClippingRange (std::max (distance - 2.0 * radius, 1e-4 * distance), distance + 2.0 * radius);
    for (int i = 0; i < n; ++i)
      rendererOf (viz, viewports[i])->SetActiveCamera (camera);

    // Render once, write to a temporary file, check it, then move it into place.
    viz.getRenderWindow ()->Render ();
    auto grab = vtkSmartPointer<vtkWindowToImageFilter>::New ();
    grab->SetInput (viz.getRenderWindow ());
    grab->SetInputBufferTypeToRGB ();
    grab->ReadFrontBufferOff ();
    grab->Update ();
    auto writer = vtkSmartPointer<vtkPNGWriter>::New ();
    writer->SetFileName (tmp.c_str ());
    writer->SetInputConnection (grab->GetOutputPort ());
    writer->Write ();
    if (writer->GetErrorCode () != 0)
      throw RenderError ("cannot write " + tmp);

    auto reader = vtkSmartPointer<vtkPNGReader>::New ();
    if (!reader->CanReadFile (tmp.c_str ()))
      throw RenderError ("the written " + tmp + " is not a readable PNG");
    reader->SetFileName (tmp.c_str ());
    reader->Update ();
    vtkImageData *image = reader->GetOutput ();
    int dims[3];
    image->GetDimensions (dims);
    const int channels = image->GetNumberOfScalarComponents ();
    if (dims[0] != width || dims[1] != height || channels < 3 || image->GetScalarType () != VTK_UNSIGNED_CHAR)
      throw RenderError ("the written PNG is " + std::to_string (dims[0]) + "x" + std::to_string (dims[1]) + " with " +
                         std::to_string (channels) + " channels, expected " + std::to_string (width) + "x" +
                         std::to_string (height) + " RGB");
    const auto *pixels = static_cast<const std::uint8_t *> (image->GetScalarPointer ());
    const int bg[3] = {static_cast<int> (std::lround (background[0] * 255)),
                       static_cast<int> (std::lround (background[1] * 255)),
                       static_cast<int> (std::lround (background[2] * 255))};
    std::vector<Coverage> coverage;
    for (int i = 0; i < n; ++i)
    {
      // Image rows run bottom-up, like the renderer's origin; skip the label's band.
      vtkRenderer *ren = rendererOf (viz, viewports[i]);
      const int *origin = ren->GetOrigin ();
      const int *size = ren->GetSize ();
      const int x0 = std::clamp (origin[0], 0, width), x1 = std::clamp (origin[0] + size[0], 0, width);
      const int y0 = std::clamp (origin[1], 0, height);
      const int y1 = std::clamp (origin[1] + size[1] - (views[i].label.empty () ? 0 : font + 20), y0, height);
      std::size_t count = 0;
      for (int y = y0; y < y1; ++y)
        for (int x = x0; x < x1; ++x)
        {
          const std::uint8_t *px = pixels + (static_cast<std::size_t> (y) * width + x) * channels;
          if (std::abs (px[0] - bg[0]) + std::abs (px[1] - bg[1]) + std::abs (px[2] - bg[2]) > 6)
            ++count;
        }
      const double area = std::max (1.0, static_cast<double> (x1 - x0) * (y1 - y0));
      const double coverable = 0.25 * static_cast<double> (views[i].cloud->size ()) * point_size * point_size;
      const auto required = static_cast<std::size_t> (std::ceil (std::max (1.0, std::min (0.005 * area, coverable))));
      coverage.push_back ({count / area, count, required});
    }
    for (int i = 0; i < n; ++i)
      if (coverage[i].pixels < coverage[i].required)
        throw RenderError ("view " + std::to_string (i + 1) + " (" + views[i].file + ") has " +
                           std::to_string (coverage[i].pixels) + " non-background pixels, fewer than the " +
                           std::to_string (coverage[i].required) +
                           " required: the cloud is not drawn, degenerate in this view, or shrunk by far "
                           "points (all clouds fit a sphere of radius " +
                           std::to_string (radius) + ")");

    std::error_code ec;
    std::filesystem::rename (tmp, opt.out, ec);
    if (ec)
      throw RenderError ("cannot move " + tmp + " to " + opt.out + ": " + ec.message ());
    std::printf ("%s %dx%d, non-background pixels:", opt.out.c_str (), width, height);
    for (int i = 0; i < n; ++i)
      std::printf ("%s %.3g%% (%s)", i ? "," : "", 100.0 * coverage[i].fraction, views[i].label.c_str ());
    std::printf ("\n");
    return 0;
  }
  catch (const InputError &e)
  {
    std::remove (tmp.c_str ());
    std::fprintf (stderr, "render_views: error: %s\n", e.what ());
    return 2;
  }
  catch (const std::exception &e)
  {
    std::remove (tmp.c_str ());
    std::fprintf (stderr, "render_views: error: %s\n", e.what ());
    return 1;
  }
}

/*
 * pcl_graph_denoise: graph-signal-processing point cloud denoising for PCL.
 * SPDX-License-Identifier: BSD-3-Clause
 *
 * Clouds side by side in one PCLVisualizer with a shared camera, viridis colours, a
 * colour bar and a checked PNG: shared by pcl_graph_denoise_viewer and bench/render_views.
 */
#include "view_render.h"

#include <pcl/visualization/common/common.h>
#include <pcl/visualization/point_cloud_color_handlers.h>

#include <vtkCamera.h>
#include <vtkImageData.h>
#include <vtkPNGReader.h>
#include <vtkPNGWriter.h>
#include <vtkRenderWindow.h>
#include <vtkRenderer.h>
#include <vtkRendererCollection.h>
#include <vtkScalarBarActor.h>
#include <vtkTextProperty.h>
#include <vtkWindowToImageFilter.h>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <limits>
#include <stdexcept>
#include <system_error>
#include <thread>

// Last: Xlib defines macros (Status, Success, None, ...) that clash with the headers above.
#include <X11/Xlib.h>

namespace pcl_graph_denoise {
namespace tools {

const char *const xvfb_hint = "xvfb-run -a -s \"-screen 0 1920x1080x24\"";

// --- The X server ---------------------------------------------------------------------

DisplayConnection::DisplayConnection ()
{
  const char *display = std::getenv ("DISPLAY");
  if (!display || !*display)
    throw std::runtime_error (std::string ("no X display (DISPLAY is not set); run under ") + xvfb_hint);
  for (int attempt = 0; attempt < 20 && !connection_; ++attempt)
  {
    if (attempt > 0)
      std::this_thread::sleep_for (std::chrono::milliseconds (100));
    connection_ = XOpenDisplay (nullptr);
  }
  if (!connection_)
    throw std::runtime_error (std::string ("cannot open the X display '") + display + "'");
}

DisplayConnection::~DisplayConnection ()
{
  XCloseDisplay (connection_);
}

// --- Arguments ------------------------------------------------------------------------

double
parseFiniteNumber (const std::string &option, const char *text)
{
  errno = 0;
  char *end = nullptr;
  const double v = std::strtod (text, &end);
  if (end == text || *end != '\0' || errno == ERANGE || !std::isfinite (v))
    throw std::invalid_argument (option + ": '" + text + "' is not a finite number");
  return v;
}

int
parsePixels (const std::string &option, const char *text)
{
  const double v = parseFiniteNumber (option, text);
  if (v != std::floor (v) || v < 100 || v > 8192)
    throw std::invalid_argument (option + ": '" + text + "' is not a whole number of pixels in [100, 8192]");
  return static_cast<int> (v);
}

void
checkViewVectors (const std::string &option, Eigen::Vector3d &direction, Eigen::Vector3d &up)
{
  if (!(direction.norm () > 0.0) || !std::isfinite (direction.norm ()))
    throw std::invalid_argument (option + ": the viewing direction must be a non-zero vector");
  if (!(up.norm () > 0.0) || !std::isfinite (up.norm ()))
    throw std::invalid_argument (option + ": the up vector must be a non-zero vector");
  direction.normalize ();
  up.normalize ();
  if (direction.cross (up).norm () < 1e-6)
    throw std::invalid_argument (option + ": the up vector is parallel to the viewing direction");
}

bool
hasPngExtension (const std::string &path)
{
  if (path.size () < 4)
    return false;
  std::string ext = path.substr (path.size () - 4);
  std::transform (ext.begin (), ext.end (), ext.begin (),
                  [] (unsigned char c) { return static_cast<char> (std::tolower (c)); });
  return ext == ".png";
}

void
checkPngWritable (const std::string &path)
{
  std::error_code ec;
  if (std::filesystem::is_directory (path, ec))
    throw std::runtime_error ("cannot write " + path + ": it is a folder");
  const std::string tmp = path + ".partial.png";
  std::FILE *f = std::fopen (tmp.c_str (), "wb");
  if (!f)
    throw std::runtime_error ("cannot write " + path + ": " + std::strerror (errno));
  std::fclose (f);
  std::remove (tmp.c_str ());
}

// --- Colours --------------------------------------------------------------------------

double
defaultPointSize (std::size_t largest_cloud)
{
  return largest_cloud < 2000 ? 4.0 : largest_cloud < 20000 ? 3.0 : 2.0;
}

void
defaultScalarRange (std::vector<double> values, double &lo, double &hi)
{
  values.erase (std::remove_if (values.begin (), values.end (), [] (double s) { return !std::isfinite (s); }),
                values.end ());
  if (values.empty ())
  {
    lo = 0.0;
    hi = 1.0;
    return;
  }
  const auto [min_it, max_it] = std::minmax_element (values.begin (), values.end ());
  const double vmin = *min_it, vmax = *max_it;
  const bool negative = vmin < 0.0;
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

vtkSmartPointer<vtkLookupTable>
makeViridisTable (double lo, double hi)
{
  vtkSmartPointer<vtkLookupTable> pcl_table;
  if (!pcl::visualization::getColormapLUT (pcl::visualization::PCL_VISUALIZER_LUT_VIRIDIS, pcl_table) &&
      !pcl::visualization::getColormapLUT (pcl::visualization::PCL_VISUALIZER_LUT_JET_INVERSE, pcl_table))
    throw std::runtime_error ("PCL provides neither the viridis nor the jet colour map");
  // Copy the colours into a table of our own: rebuilding PCL's after a range change
  // could replace its colours with the default hue ramp.
  const vtkIdType n = pcl_table->GetNumberOfTableValues ();
  auto table = vtkSmartPointer<vtkLookupTable>::New ();
  table->SetTableRange (lo, hi);
  table->SetNumberOfTableValues (n);
  table->Build ();
  for (vtkIdType i = 0; i < n; ++i)
  {
    double rgba[4];
    pcl_table->GetTableValue (i, rgba);
    table->SetTableValue (i, rgba[0], rgba[1], rgba[2], 1.0);
  }
  table->SetNanColor (nan_colour[0] / 255.0, nan_colour[1] / 255.0, nan_colour[2] / 255.0, 1.0);
  return table;
}

void
colourByScalar (ColouredCloud &cloud, const std::vector<double> &scalar, vtkLookupTable &table)
{
  const double *range = table.GetTableRange ();
  const double lo = range[0], hi = range[1];
  const vtkIdType n = table.GetNumberOfTableValues ();
  for (std::size_t i = 0; i < cloud.size () && i < scalar.size (); ++i)
  {
    auto &q = cloud[i];
    const double s = scalar[i];
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
    table.GetTableValue (k, rgba);
    q.r = static_cast<std::uint8_t> (std::lround (rgba[0] * 255.0));
    q.g = static_cast<std::uint8_t> (std::lround (rgba[1] * 255.0));
    q.b = static_cast<std::uint8_t> (std::lround (rgba[2] * 255.0));
  }
}

// --- The window -----------------------------------------------------------------------

int
SideBySideViews::colourBarStrip (int height)
{
  return std::clamp (static_cast<int> (std::lround (0.1 * height)), 50, 120);
}

bool
SideBySideViews::fits (int views, int width, int height, bool colour_bar)
{
  return views >= 1 && views <= max_views && height - (colour_bar ? colourBarStrip (height) : 0) >= 50 &&
         width / views >= 50;
}

SideBySideViews::SideBySideViews (const std::string &name, int views, int width, int height, bool colour_bar,
                                  bool interactive)
: viz_ (new pcl::visualization::PCLVisualizer (name, interactive))
, width_ (width)
, height_ (height)
, strip_ (colour_bar ? colourBarStrip (height) : 0)
, font_ (std::clamp (static_cast<int> (std::lround (0.03 * height)), 12, 40))
, viewports_ (static_cast<std::size_t> (views), 0)
, labels_ (static_cast<std::size_t> (views))
, sizes_ (static_cast<std::size_t> (views), 0)
, point_sizes_ (static_cast<std::size_t> (views), 1.0)
{
  if (!interactive)
    viz_->getRenderWindow ()->SetOffScreenRendering (1);
  viz_->setSize (width, height);
  viz_->setShowFPS (false);
  const double strip_top = static_cast<double> (strip_) / height;
  for (int i = 0; i < views; ++i)
    viz_->createViewPort (static_cast<double> (i) / views, strip_top, static_cast<double> (i + 1) / views, 1.0,
                          viewports_[i]);
  if (colour_bar)
  {
    viz_->createViewPort (0.0, 0.0, 1.0, strip_top, bar_viewport_);
    // The bar's strip neither moves the shared camera nor is moved by it.
    viz_->createViewPortCamera (bar_viewport_);
    renderer (bar_viewport_)->InteractiveOff ();
  }
  viz_->setBackgroundColor (view_background[0], view_background[1], view_background[2]);  // every renderer
}

vtkRenderer *
SideBySideViews::renderer (int viewport) const
{
  return vtkRenderer::SafeDownCast (viz_->getRendererCollection ()->GetItemAsObject (viewport));
}

void
SideBySideViews::addCloud (int view, const ColouredCloud::ConstPtr &cloud, const std::string &label,
                           double point_size)
{
  const std::string id = "cloud" + std::to_string (view);
  pcl::visualization::PointCloudColorHandlerRGBField<pcl::PointXYZRGB> colours (cloud);
  if (!viz_->addPointCloud<pcl::PointXYZRGB> (cloud, colours, id, viewports_[view]))
    throw std::runtime_error ("PCLVisualizer refused the cloud of view " + std::to_string (view + 1));
  viz_->setPointCloudRenderingProperties (pcl::visualization::PCL_VISUALIZER_POINT_SIZE, point_size, id);
  if (!label.empty ())
    viz_->addText (label, 10, height_ - strip_ - font_ - 10, font_, 0.1, 0.1, 0.1, "label" + std::to_string (view),
                   viewports_[view]);
  labels_[view] = label;
  sizes_[view] = cloud->size ();
  point_sizes_[view] = point_size;
}

void
SideBySideViews::addColourBar (vtkLookupTable *table, const std::string &title)
{
  if (bar_viewport_ < 0)
    return;
  auto bar = vtkSmartPointer<vtkScalarBarActor>::New ();
  bar->SetLookupTable (table);
  bar->SetOrientationToHorizontal ();
  bar->SetTitle (title.c_str ());
  bar->SetNumberOfLabels (width_ >= 1200 ? 5 : 3);  // room for "-0.0001234"-wide labels
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
  renderer (bar_viewport_)->AddActor2D (bar);
}

double
SideBySideViews::fitCamera (const std::vector<ColouredCloud::ConstPtr> &clouds, const Eigen::Vector3d &direction,
                            const Eigen::Vector3d &up)
{
  Eigen::Vector3d min_pt = Eigen::Vector3d::Constant (std::numeric_limits<double>::max ());
  Eigen::Vector3d max_pt = -min_pt;
  std::size_t points = 0;
  for (const auto &cloud : clouds)
    for (const auto &p : *cloud)
    {
      const Eigen::Vector3d q = p.getVector3fMap ().cast<double> ();
      min_pt = min_pt.cwiseMin (q);
      max_pt = max_pt.cwiseMax (q);
      ++points;
    }
  const Eigen::Vector3d centre = points > 0 ? Eigen::Vector3d (0.5 * (min_pt + max_pt)) : Eigen::Vector3d::Zero ();
  double radius = 0.0;
  for (const auto &cloud : clouds)
    for (const auto &p : *cloud)
      radius = std::max (radius, (p.getVector3fMap ().cast<double> () - centre).norm ());
  radius = std::max (radius, 1e-3 * std::max (1.0, centre.cwiseAbs ().maxCoeff ()));

  const int n = static_cast<int> (viewports_.size ());
  const double view_angle = 30.0;  // vertical, degrees
  const double aspect = (static_cast<double> (width_) / n) / (height_ - strip_);
  const double half_v = 0.5 * view_angle * M_PI / 180.0;
  const double half = std::min (half_v, std::atan (std::tan (half_v) * aspect));
  const double distance = 1.05 * radius / std::sin (half);
  const Eigen::Vector3d eye = centre - distance * direction;
  vtkCamera *camera = renderer (viewports_[0])->GetActiveCamera ();
  camera->SetViewAngle (view_angle);
  camera->SetFocalPoint (centre.x (), centre.y (), centre.z ());
  camera->SetPosition (eye.x (), eye.y (), eye.z ());
  camera->SetViewUp (up.x (), up.y (), up.z ());
  camera->OrthogonalizeViewUp ();
  camera->SetClippingRange (std::max (distance - 2.0 * radius, 1e-4 * distance), distance + 2.0 * radius);
  for (int i = 0; i < n; ++i)
    renderer (viewports_[i])->SetActiveCamera (camera);
  // The full-window renderer behind the viewports too, so that any reset keeps one camera.
  renderer (0)->SetActiveCamera (camera);
  return radius;
}

std::vector<ViewCoverage>
SideBySideViews::writeCheckedPng (const std::string &path, const std::vector<std::string> &names, double radius)
{
  const std::string tmp = path + ".partial.png";
  try
  {
    viz_->getRenderWindow ()->Render ();
    auto grab = vtkSmartPointer<vtkWindowToImageFilter>::New ();
    grab->SetInput (viz_->getRenderWindow ());
    grab->SetInputBufferTypeToRGB ();
    grab->ReadFrontBufferOff ();
    grab->Update ();
    auto writer = vtkSmartPointer<vtkPNGWriter>::New ();
    writer->SetFileName (tmp.c_str ());
    writer->SetInputConnection (grab->GetOutputPort ());
    writer->Write ();
    if (writer->GetErrorCode () != 0)
      throw std::runtime_error ("cannot write " + tmp);

    auto reader = vtkSmartPointer<vtkPNGReader>::New ();
    if (!reader->CanReadFile (tmp.c_str ()))
      throw std::runtime_error ("the written " + tmp + " is not a readable PNG");
    reader->SetFileName (tmp.c_str ());
    reader->Update ();
    vtkImageData *image = reader->GetOutput ();
    int dims[3];
    image->GetDimensions (dims);
    const int channels = image->GetNumberOfScalarComponents ();
    if (dims[0] != width_ || dims[1] != height_ || channels < 3 || image->GetScalarType () != VTK_UNSIGNED_CHAR)
      throw std::runtime_error ("the written PNG is " + std::to_string (dims[0]) + "x" + std::to_string (dims[1]) +
                                " with " + std::to_string (channels) + " channels, expected " +
                                std::to_string (width_) + "x" + std::to_string (height_) + " RGB");
    const auto *pixels = static_cast<const std::uint8_t *> (image->GetScalarPointer ());
    int bg[3];
    for (int c = 0; c < 3; ++c)
      bg[c] = static_cast<int> (std::lround (view_background[c] * 255));

    std::vector<ViewCoverage> coverage;
    for (std::size_t i = 0; i < viewports_.size (); ++i)
    {
      // Image rows run bottom-up, like the renderer's origin; skip the label's band.
      vtkRenderer *ren = renderer (viewports_[i]);
      const int *origin = ren->GetOrigin ();
      const int *size = ren->GetSize ();
      const int x0 = std::clamp (origin[0], 0, width_), x1 = std::clamp (origin[0] + size[0], 0, width_);
      const int y0 = std::clamp (origin[1], 0, height_);
      const int y1 = std::clamp (origin[1] + size[1] - (labels_[i].empty () ? 0 : font_ + 20), y0, height_);
      ViewCoverage c;
      for (int y = y0; y < y1; ++y)
        for (int x = x0; x < x1; ++x)
        {
          const std::uint8_t *px = pixels + (static_cast<std::size_t> (y) * width_ + x) * channels;
          if (std::abs (px[0] - bg[0]) + std::abs (px[1] - bg[1]) + std::abs (px[2] - bg[2]) > 6)
            ++c.pixels;
        }
      const double area = std::max (1.0, static_cast<double> (x1 - x0) * (y1 - y0));
      const double coverable = 0.25 * static_cast<double> (sizes_[i]) * point_sizes_[i] * point_sizes_[i];
      c.required = static_cast<std::size_t> (std::ceil (std::max (1.0, std::min (0.005 * area, coverable))));
      c.fraction = c.pixels / area;
      coverage.push_back (c);
    }
    for (std::size_t i = 0; i < coverage.size (); ++i)
      if (coverage[i].pixels < coverage[i].required)
        throw std::runtime_error (
            "view " + std::to_string (i + 1) + " (" + (i < names.size () ? names[i] : labels_[i]) + ") has " +
            std::to_string (coverage[i].pixels) + " non-background pixels, fewer than the " +
            std::to_string (coverage[i].required) +
            " required: the cloud is not drawn, degenerate in this view, or shrunk by far points (the camera "
            "fits a sphere of radius " +
            std::to_string (radius) + ")");

    std::error_code ec;
    std::filesystem::rename (tmp, path, ec);
    if (ec)
      throw std::runtime_error ("cannot move " + tmp + " to " + path + ": " + ec.message ());
    return coverage;
  }
  catch (...)
  {
    std::remove (tmp.c_str ());
    throw;
  }
}

void
SideBySideViews::spin ()
{
  viz_->spin ();
}

std::string
describeCoverage (const std::string &path, int width, int height, const std::vector<ViewCoverage> &coverage,
                  const std::vector<std::string> &labels)
{
  std::string text = path + " " + std::to_string (width) + "x" + std::to_string (height) + ", non-background pixels:";
  for (std::size_t i = 0; i < coverage.size (); ++i)
  {
    char percent[32];
    std::snprintf (percent, sizeof (percent), "%.3g%%", 100.0 * coverage[i].fraction);
    text += std::string (i ? ", " : " ") + percent + " (" + (i < labels.size () ? labels[i] : "") + ")";
  }
  return text;
}

}  // namespace tools
}  // namespace pcl_graph_denoise

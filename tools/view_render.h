/*
 * pcl_graph_denoise: graph-signal-processing point cloud denoising for PCL.
 * SPDX-License-Identifier: BSD-3-Clause
 */
#pragma once

#include <pcl/point_cloud.h>
#include <pcl/point_types.h>
#include <pcl/visualization/pcl_visualizer.h>

#include <vtkLookupTable.h>
#include <vtkSmartPointer.h>

#include <Eigen/Core>

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

// Forward declaration: Xlib's macros (Status, Success, None, ...) stay out of every
// file that includes this header.
struct _XDisplay;

namespace pcl_graph_denoise {
namespace tools {

/** \brief What side-by-side views draw: finite points only, each with its colour. */
using ColouredCloud = pcl::PointCloud<pcl::PointXYZRGB>;

/** \brief Background of every view: white. */
constexpr double view_background[3] = {1.0, 1.0, 1.0};

/** \brief Colour of a point whose scalar is not finite: grey. */
constexpr std::uint8_t nan_colour[3] = {160, 160, 160};

/** \brief A connection to the X server, held while VTK opens its own.
 *
 * VTK aborts the process when it cannot connect, so the connection is tried first. An X
 * server started without -noreset (xvfb-run's default) resets when its last client
 * leaves and refuses connections meanwhile: connecting is retried for two seconds, and
 * the connection is kept open so that the server cannot reset before VTK has connected.
 * Create it before, and destroy it after, the PCLVisualizer. */
class DisplayConnection
{
public:
  /** \throws std::runtime_error (one line, suggesting xvfb-run) if DISPLAY is not set
   *  or the server cannot be reached. */
  DisplayConnection ();
  ~DisplayConnection ();
  DisplayConnection (const DisplayConnection &) = delete;
  DisplayConnection &
  operator= (const DisplayConnection &) = delete;

private:
  _XDisplay *connection_ = nullptr;
};

/** \brief The command to run a viewer without a display, for messages. */
extern const char *const xvfb_hint;

/** \brief A whole argument as a finite number.
 *  \throws std::invalid_argument naming `option`. */
double
parseFiniteNumber (const std::string &option, const char *text);

/** \brief A whole argument as a window size in pixels, in [100, 8192].
 *  \throws std::invalid_argument naming `option`. */
int
parsePixels (const std::string &option, const char *text);

/** \brief Checks a viewing direction and an up vector (non-zero, finite, not
 *  parallel) and normalises both.
 *  \throws std::invalid_argument naming `option`. */
void
checkViewVectors (const std::string &option, Eigen::Vector3d &direction, Eigen::Vector3d &up);

/** \brief True when the path ends in .png (any case). */
bool
hasPngExtension (const std::string &path);

/** \brief Fails early when a PNG cannot be written at `path` (missing folder, no
 *  permission), before anything is rendered: creates and removes `path` + ".partial.png".
 *  \throws std::runtime_error "cannot write PATH: reason". */
void
checkPngWritable (const std::string &path);

/** \brief Default point size in pixels for the largest cloud shown: 2, or 3 below 20000
 *  points, 4 below 2000. */
double
defaultPointSize (std::size_t largest_cloud);

/** \brief Default colour range of a scalar: 0 to the 98th percentile of the finite
 *  values, or -a to a (a the 98th percentile of |value|) when a value is negative; the
 *  whole range when that is empty, [0, 1] without a finite value. */
void
defaultScalarRange (std::vector<double> values, double &lo, double &hi);

/** \brief PCL's viridis colour map (else its inverse jet) over [lo, hi]; values out of
 *  the range clamp, NaN is nan_colour.
 *  \throws std::runtime_error if PCL provides neither map. */
vtkSmartPointer<vtkLookupTable>
makeViridisTable (double lo, double hi);

/** \brief Colours point i of `cloud` by `scalar[i]` through `table` (over its range),
 *  nan_colour where the scalar is not finite. */
void
colourByScalar (ColouredCloud &cloud, const std::vector<double> &scalar, vtkLookupTable &table);

/** \brief Pixels of one view that differ from the background, in the picture written. */
struct ViewCoverage
{
  double fraction = 0.0;      ///< pixels / area of the view outside its label
  std::size_t pixels = 0;     ///< non-background pixels
  std::size_t required = 0;   ///< at least this many: min(0.5% of the area, a quarter of
                              ///< what the points can cover at their point size), >= 1
};

/** \brief One to three clouds side by side in one PCLVisualizer window, one viewport
 *  each above an optional strip for a colour bar, all seen through one shared camera:
 *  moving one view moves them all.
 *
 * Interactive (a window and an interactor, spin()) or off-screen (render once,
 * writeCheckedPng()). Either way an X server is needed: create a DisplayConnection
 * first. */
class SideBySideViews
{
public:
  /** \brief Most views in one window. */
  static constexpr int max_views = 3;

  /** \brief Height in pixels of the strip for the colour bar in a window of `height`. */
  static int
  colourBarStrip (int height);

  /** \brief True when `views` views (and the strip, if `colour_bar`) fit the size. */
  static bool
  fits (int views, int width, int height, bool colour_bar);

  /** \brief Opens the window (or the off-screen one) with white viewports.
   *  \param[in] name window title
   *  \param[in] views number of viewports, 1 to max_views
   *  \param[in] width, height window size in pixels; must fit (see fits())
   *  \param[in] colour_bar leave a strip at the bottom for addColourBar()
   *  \param[in] interactive a window with an interactor, else off-screen rendering */
  SideBySideViews (const std::string &name, int views, int width, int height, bool colour_bar,
                   bool interactive);

  /** \brief Draws `cloud` (coloured by its rgb) in view `view` (0-based) at
   *  `point_size` pixels, with `label` in its top left corner (none if empty).
   *  \throws std::runtime_error if PCLVisualizer refuses the cloud. */
  void
  addCloud (int view, const ColouredCloud::ConstPtr &cloud, const std::string &label,
            double point_size);

  /** \brief A horizontal colour bar for `table` in the strip under the views. */
  void
  addColourBar (vtkLookupTable *table, const std::string &title);

  /** \brief Places the shared camera so that it sees the bounding sphere of `clouds`
   *  from `direction` (unit vector from the camera towards the centre) with `up` (unit)
   *  upwards, with a 30 degree view angle.
   *  \return the radius of that sphere. */
  double
  fitCamera (const std::vector<ColouredCloud::ConstPtr> &clouds, const Eigen::Vector3d &direction,
             const Eigen::Vector3d &up);

  /** \brief Renders once, writes the picture to `path` + ".partial.png", reads it back
   *  and measures what each view shows (outside its label); if every view shows at least
   *  its required pixels the file is renamed to `path`, else it is removed.
   *  \param[in] names each view's name for the message, e.g. its file
   *  \param[in] radius the camera's bounding sphere, for the message
   *  \throws std::runtime_error (one line) when writing, reading back or the check fails;
   *  no file is left then. */
  std::vector<ViewCoverage>
  writeCheckedPng (const std::string &path, const std::vector<std::string> &names, double radius);

  /** \brief Runs the interactor until the window is closed (interactive only). */
  void
  spin ();

  /** \brief The visualizer, for anything else. */
  pcl::visualization::PCLVisualizer &
  visualizer ()
  {
    return *viz_;
  }

  int
  width () const
  {
    return width_;
  }

  int
  height () const
  {
    return height_;
  }

private:
  /** \brief The renderer of a viewport. */
  vtkRenderer *
  renderer (int viewport) const;

  pcl::visualization::PCLVisualizer::Ptr viz_;
  int width_, height_, strip_, font_;
  int bar_viewport_ = -1;
  std::vector<int> viewports_;
  std::vector<std::string> labels_;
  std::vector<std::size_t> sizes_;      ///< points drawn in each view
  std::vector<double> point_sizes_;     ///< their size in pixels
};

/** \brief "out.png 1600x800, non-background pixels: 12.3% (input), 11.8% (result)". */
std::string
describeCoverage (const std::string &path, int width, int height,
                  const std::vector<ViewCoverage> &coverage, const std::vector<std::string> &labels);

}  // namespace tools
}  // namespace pcl_graph_denoise

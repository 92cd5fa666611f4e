/*
 * pcl_graph_denoise: graph-signal-processing point cloud denoising for PCL.
 * SPDX-License-Identifier: BSD-3-Clause
 */
#pragma once

#include <pcl/filters/filter_indices.h>

namespace pcl_graph_denoise {

/** \brief Removes outliers by their weighted degree in an epsilon-radius graph
 *  (Schoenenberger, Paratte, Vandergheynst, "Graph-based denoising for time-varying
 *  point clouds", 2015, section 3.1).
 *
 * Every finite point named by the indices is linked to the other finite points of the
 * input cloud closer than epsilon, with the Gaussian weight exp(-d^2 / (2 theta^2)): as
 * in PCL's StatisticalOutlierRemoval, the indices name the points tested and the whole
 * cloud is searched for their neighbours (the derived defaults come from the named
 * points, as SOR's statistics do). A point's degree is the
 * sum of its weights: an outlier has few close neighbours and a low degree. Points
 * whose degree is below the threshold tau are removed; alternatively, a given
 * fraction of the lowest-degree points is removed (the paper's percentile rule).
 * An outlier that lands within a couple of spacings of the surface has an inlier's
 * degree; a second test, on by default, removes it by its distance to the plane of its
 * neighbours (setResidualThreshold(); 0 gives the paper's filter exactly).
 *
 * Defaults are derived from the data, so that the same cloud in millimetres or in
 * metres gives the same result (see the setters). Points with a non-finite
 * coordinate are always removed (also with setNegative(true)) and are never used
 * as queries or as neighbours. A few points with garbage coordinates (more than 5e17 from
 * the others' median along an axis, e.g. a "no return" marker at 1e20; fewer than half
 * the points) are outliers beyond any search: removed (kept with setNegative(true)), with
 * a PCL_WARN. The full pcl::FilterIndices contract holds:
 * indices, negative mode, removed indices, organised output, in-place use.
 *
 * Invalid parameters or indices are reported with PCL_ERROR when filter() runs,
 * which then returns an empty result; nothing throws out of filter().
 *
 * \code
 * pcl_graph_denoise::GraphDegreeOutlierRemoval<pcl::PointXYZ> outliers;
 * outliers.setInputCloud (cloud);
 * outliers.filter (*cleaned);   // all parameters derived from the data
 * \endcode
 */
template <typename PointT>
class GraphDegreeOutlierRemoval : public pcl::FilterIndices<PointT>
{
protected:
  using PointCloud = typename pcl::FilterIndices<PointT>::PointCloud;  ///< the cloud type filtered
  using pcl::FilterIndices<PointT>::extract_removed_indices_;
  using pcl::FilterIndices<PointT>::fake_indices_;
  using pcl::FilterIndices<PointT>::filter_name_;
  using pcl::FilterIndices<PointT>::getClassName;
  using pcl::FilterIndices<PointT>::indices_;
  using pcl::FilterIndices<PointT>::keep_organized_;
  using pcl::FilterIndices<PointT>::input_;
  using pcl::FilterIndices<PointT>::negative_;
  using pcl::FilterIndices<PointT>::removed_indices_;

public:
  using Ptr = std::shared_ptr<GraphDegreeOutlierRemoval<PointT>>;  ///< shared pointer, as PCL's filters
  using ConstPtr = std::shared_ptr<const GraphDegreeOutlierRemoval<PointT>>;  ///< shared pointer to const

  /** \brief How the degree threshold is chosen. */
  enum ThresholdRule
  {
    AUTOMATIC_THRESHOLD,  ///< tau = getAutomaticThresholdRatio() x first quartile of the degrees (default)
    ABSOLUTE_THRESHOLD,   ///< tau as given to setDegreeThreshold()
    OUTLIER_FRACTION      ///< remove the fraction given to setOutlierFraction()
  };

  /** \brief Constructor.
   *  \param[in] extract_removed_indices set to true to retrieve the removed points'
   *  indices with getRemovedIndices(). */
  explicit GraphDegreeOutlierRemoval (bool extract_removed_indices = false)
  : pcl::FilterIndices<PointT> (extract_removed_indices)
  {
    filter_name_ = "GraphDegreeOutlierRemoval";
  }

  /** \brief Radius epsilon of the graph, in the cloud's units: points closer than
   *  epsilon are linked. Default 0 = derived from the data: 3 x the spacing, the median
   *  over the points of their mean distance to their 10 nearest neighbours (over the
   *  distinct positions when there are exact copies: they do not make the surface
   *  denser).
   *  Valid: finite, >= 0. */
  inline void
  setRadiusSearch (double epsilon) { radius_ = epsilon; }

  /** \brief The radius set (0 = derived from the data). */
  inline double
  getRadiusSearch () const { return radius_; }

  /** \brief Kernel width theta of the weights exp(-d^2 / (2 theta^2)), in the cloud's
   *  units. Default 0 = derived from the data: theta = the spacing (see setRadiusSearch).
   *  Valid: finite, >= 0. */
  inline void
  setSigma (double theta) { sigma_ = theta; }

  /** \brief The kernel width set (0 = derived from the data). */
  inline double
  getSigma () const { return sigma_; }

  /** \brief Removes the points whose weighted degree is below tau (unitless: a sum of
   *  weights in [0, 1]). Selects ABSOLUTE_THRESHOLD. Valid: finite, >= 0. */
  inline void
  setDegreeThreshold (double tau)
  {
    degree_threshold_ = tau;
    rule_ = ABSOLUTE_THRESHOLD;
  }

  /** \brief The absolute threshold set (used with ABSOLUTE_THRESHOLD). */
  inline double
  getDegreeThreshold () const { return degree_threshold_; }

  /** \brief Removes instead the fraction p of the finite points with the lowest
   *  degree (round(p x count) points; among equal degrees, such as the 0 of every
   *  isolated point, the more isolated go first: larger mean distance to their 10
   *  nearest neighbours, then by index). Selects
   *  OUTLIER_FRACTION. Valid: 0 <= p <= 1. */
  inline void
  setOutlierFraction (double p)
  {
    outlier_fraction_ = p;
    rule_ = OUTLIER_FRACTION;
  }

  /** \brief The fraction set (used with OUTLIER_FRACTION). */
  inline double
  getOutlierFraction () const { return outlier_fraction_; }

  /** \brief Chooses tau from the data: tau = ratio x the first quartile of the degrees
   *  of the finite points (a quartile, so that up to a quarter of outliers do not pull it
   *  down; when more than a quarter have no neighbour at all, the quartile of the others,
   *  with a PCL_WARN). Selects AUTOMATIC_THRESHOLD (the default rule). Default ratio 0.2.
   *  Valid: finite, >= 0. */
  inline void
  setAutomaticThresholdRatio (double ratio)
  {
    automatic_ratio_ = ratio;
    rule_ = AUTOMATIC_THRESHOLD;
  }

  /** \brief The ratio used by AUTOMATIC_THRESHOLD. */
  inline double
  getAutomaticThresholdRatio () const { return automatic_ratio_; }

  /** \brief Second test, on the points the degree test keeps: removes a point lying
   *  off the surface its epsilon-neighbours sample by more than `multiplier` times the
   *  noise. Its residual is its distance to the plane fitted to its neighbours (refitted
   *  without the neighbours off it), i.e. the normal component of the random-walk
   *  Laplacian (I - D^-1 W) of its coordinates; the noise is the larger of the cloud's
   *  scale (the median residual / 0.6745, getUsedResidualScale()) and the plane's own
   *  spread. Points on sharp edges, corners and steps, and points with another two level
   *  with them off the plane (a layer, not an outlier), are kept (details:
   *  core::RadiusDegrees::off_surface). It catches the outliers close to the surface, whose
   *  degree is an inlier's. 0 turns it off (the paper's filter). Not applied with
   *  setOutlierFraction(), which removes an exact count. Default 4. Valid: >= 0, finite. */
  inline void
  setResidualThreshold (double multiplier) { residual_multiplier_ = multiplier; }

  /** \brief The residual multiplier set (0: no residual test). */
  inline double
  getResidualThreshold () const { return residual_multiplier_; }

  /** \brief With AUTOMATIC_THRESHOLD (the default rule), keeps the points below the
   *  threshold that continue a surface sampled more sparsely than the rest of the cloud:
   *  a laser scanner's or a depth camera's spacing grows with the range, and a far wall
   *  whose points are several epsilons apart would otherwise be removed whole (on PCL's
   *  room scan, room_scan1.pcd, 67% of the points 5-6 m from the scanner and all beyond
   *  8 m). Such points are reached from the cloud's typical points through neighbours
   *  whose density changes gradually and which lie on a plane; an isolated outlier, a
   *  cloud of uniform outliers and points off the surface are still removed (details:
   *  core::RadiusDegrees::sparse_surface). Not applied with the other two rules, whose
   *  threshold or count the caller chose. Default true. */
  inline void
  setKeepSparseSurfaces (bool keep) { keep_sparse_surfaces_ = keep; }

  /** \brief Whether sparse surfaces are kept (see setKeepSparseSurfaces). */
  inline bool
  getKeepSparseSurfaces () const { return keep_sparse_surfaces_; }

  /** \brief The rule in force (set by the last of the three setters above). */
  inline ThresholdRule
  getThresholdRule () const { return rule_; }

  /** \brief Worker threads; 0 (default) = all hardware threads. The result does not
   *  depend on it. Valid: >= 0. */
  inline void
  setNumberOfThreads (int num_threads) { num_threads_ = num_threads; }

  /** \brief The number of threads set. */
  inline int
  getNumberOfThreads () const { return num_threads_; }

  /** \brief Memory the filter may use, in bytes (default 0: the machine's physical
   *  memory). filter() first estimates its peak for the input (estimateMemory) and,
   *  when that is above the limit, prints a PCL_ERROR with both figures and returns
   *  nothing kept, nothing removed, before allocating anything. */
  inline void
  setMemoryLimit (std::size_t bytes) { memory_limit_ = bytes; }

  /** \brief The memory limit set (0: the machine's physical memory). */
  inline std::size_t
  getMemoryLimit () const { return memory_limit_; }

  /** \brief Estimated peak memory, in bytes, of filtering a cloud of `num_points`
   *  points (a filtered cloud as output included, the input not): an upper bound of
   *  what bench/bench_memory measures (docs/reliability.md). */
  std::size_t
  estimateMemory (std::size_t num_points) const;

  /** \brief Epsilon used by the last filter() call (after derivation), 0 before and
   *  after a call that failed (as are the other getUsed values). */
  inline double
  getUsedRadius () const { return used_radius_; }

  /** \brief Theta used by the last filter() call (after derivation), 0 before. */
  inline double
  getUsedSigma () const { return used_sigma_; }

  /** \brief Threshold used by the last filter() call: points with a degree below it
   *  were outliers. */
  inline double
  getUsedDegreeThreshold () const { return used_threshold_; }

  /** \brief Noise scale of the residual test in the last filter() call, in the cloud's
   *  units (points off their neighbours' plane by more than the multiplier times the
   *  larger of it and their plane's own spread were removed); 0 when the test was off. */
  inline double
  getUsedResidualScale () const { return used_residual_scale_; }

protected:
  /** \brief Filtered results are indexed by an indices array. */
  void
  applyFilter (pcl::Indices &indices) override;

  /** \brief pcl::FilterIndices' output (kept points, or with setKeepOrganized(true) the
   *  cloud with the removed points replaced), empty after an error: PCL's organised
   *  path would return a copy of the whole input. */
  void
  applyFilter (PointCloud &output) override;

private:
  /** Default epsilon and theta as multiples of the spacing (and automatic_ratio_'s 0.2,
   *  below): chosen on noisy spheres and cubes with 5% and 20% uniform outliers (100k and 1M points,
   *  noise 0.2% and 0.5% of the radius) for the best mean F1 score, while removing about
   *  1% of a real stereo scan (bench/bench_graph.cpp prints the figures). */
  static constexpr double kRadiusFactor = 3.0;
  static constexpr double kSigmaFactor = 1.0;

  /** \brief Empty the result after an error. */
  void
  fail (pcl::Indices &indices);

  double radius_ = 0.0;
  double sigma_ = 0.0;
  double degree_threshold_ = 0.0;
  double outlier_fraction_ = 0.0;
  double automatic_ratio_ = 0.2;
  double residual_multiplier_ = 4.0;
  bool keep_sparse_surfaces_ = true;
  ThresholdRule rule_ = AUTOMATIC_THRESHOLD;
  int num_threads_ = 0;
  std::size_t memory_limit_ = 0;

  double used_radius_ = 0.0;
  double used_sigma_ = 0.0;
  double used_threshold_ = 0.0;
  double used_residual_scale_ = 0.0;
  bool failed_ = false;  ///< the last applyFilter (indices) reported an error
};

} // namespace pcl_graph_denoise

#ifdef PCL_NO_PRECOMPILE
#include <pcl_graph_denoise/impl/graph_degree_outlier_removal.hpp>
#endif

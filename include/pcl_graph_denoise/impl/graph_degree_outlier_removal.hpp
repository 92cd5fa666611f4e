/*
 * pcl_graph_denoise: graph-signal-processing point cloud denoising for PCL.
 * SPDX-License-Identifier: BSD-3-Clause
 */
#pragma once

#include <pcl_graph_denoise/core/graph.h>
#include <pcl_graph_denoise/core/memory.h>
#include <pcl_graph_denoise/graph_degree_outlier_removal.h>
#include <pcl_graph_denoise/point_cloud_adaptor.h>

#include <pcl/console/print.h>

#include <algorithm>
#include <cmath>
#include <exception>
#include <limits>
#include <numeric>
#include <string>

namespace pcl_graph_denoise {

template <typename PointT>
void
GraphDegreeOutlierRemoval<PointT>::fail (pcl::Indices &indices)
{
  indices.clear ();
  removed_indices_->clear ();
  failed_ = true;
}

template <typename PointT>
void
GraphDegreeOutlierRemoval<PointT>::applyFilter (PointCloud &output)
{
  // After an error the index list is empty, and PCL's own path gives what its filters
  // give on an error (an empty cloud, width 0, height 1, the input's header and density);
  // only with setKeepOrganized would it give the input with every point replaced.
  pcl::FilterIndices<PointT>::applyFilter (output);
  if (failed_ && keep_organized_)
  {
    output.clear ();
    output.height = 1;
    output.is_dense = input_->is_dense;
  }
}

template <typename PointT>
std::size_t
GraphDegreeOutlierRemoval<PointT>::estimateMemory (std::size_t num_points) const
{
  // The PCL layer: an output cloud and the per-point flags (the gathered points, their
  // degrees and the index lists are in the core's figure, which was measured with them).
  const long double layer = static_cast<long double> (num_points) * (sizeof (PointT) + 8);
  const long double total = layer + core::radiusDegreesMemory (num_points);
  const long double most = static_cast<long double> (std::numeric_limits<std::size_t>::max ());
  return total >= most ? std::numeric_limits<std::size_t>::max () : static_cast<std::size_t> (total);
}

template <typename PointT>
void
GraphDegreeOutlierRemoval<PointT>::applyFilter (pcl::Indices &indices)
{
  failed_ = false;
  used_radius_ = used_sigma_ = used_threshold_ = used_residual_scale_ = 0.0;
  const std::string name = getClassName ();
  const auto invalid = [&] (const char *parameter, double value, const char *range) {
    PCL_ERROR ("[pcl_graph_denoise::%s::applyFilter] Invalid %s = %g: must be %s.\n",
               name.c_str (), parameter, value, range);
    fail (indices);
  };
  if (!(std::isfinite (radius_) && radius_ >= 0.0))
    return invalid ("radius (setRadiusSearch)", radius_, "finite and >= 0");
  if (!(std::isfinite (sigma_) && sigma_ >= 0.0))
    return invalid ("sigma (setSigma)", sigma_, "finite and >= 0");
  if (rule_ == ABSOLUTE_THRESHOLD && !(std::isfinite (degree_threshold_) && degree_threshold_ >= 0.0))
    return invalid ("degree threshold (setDegreeThreshold)", degree_threshold_, "finite and >= 0");
  if (rule_ == OUTLIER_FRACTION && !(outlier_fraction_ >= 0.0 && outlier_fraction_ <= 1.0))
    return invalid ("outlier fraction (setOutlierFraction)", outlier_fraction_, "in [0, 1]");
  if (rule_ == AUTOMATIC_THRESHOLD && !(std::isfinite (automatic_ratio_) && automatic_ratio_ >= 0.0))
    return invalid ("threshold ratio (setAutomaticThresholdRatio)", automatic_ratio_,
                    "finite and >= 0");
  if (!(std::isfinite (residual_multiplier_) && residual_multiplier_ >= 0.0))
    return invalid ("residual multiplier (setResidualThreshold)", residual_multiplier_,
                    "finite and >= 0");
  if (num_threads_ < 0)
    return invalid ("number of threads (setNumberOfThreads)", num_threads_, ">= 0");
  const std::string bad_index = checkIndices (*input_, *indices_);
  if (!bad_index.empty ())
  {
    PCL_ERROR ("[pcl_graph_denoise::%s::applyFilter] Invalid indices: %s.\n", name.c_str (),
               bad_index.c_str ());
    return fail (indices);
  }

  try
  {
    core::requireMemory (estimateMemory (input_->size ()), memory_limit_,
                         "removing the outliers of " + std::to_string (input_->size ()) + " points",
                         "");  // its memory grows with the points alone
  }
  catch (const std::exception &e)
  {
    PCL_ERROR ("[pcl_graph_denoise::%s::applyFilter] %s.\n", name.c_str (), e.what ());
    return fail (indices);
  }

  GatheredPoints gathered = gatherFinitePoints (*input_, *indices_, name.c_str ());
  // Garbage coordinates far beyond the rest (e.g. 1e20): outliers beyond doubt.
  takeOutFarPoints (*input_, gathered, name.c_str (),
                    "they are outliers (removed; kept with setNegative)");
  addSearchSurface (*input_, gathered, name.c_str ());

  // Degree of every gathered row.
  const std::size_t count = gathered.cloud_index.size ();
  if (count == 0)
    PCL_ERROR ("[pcl_graph_denoise::%s::applyFilter] Nothing to filter: %s.\n", name.c_str (),
               noFinitePointReason (input_->size (), indices_->size (), !fake_indices_).c_str ());
  std::vector<double> degree;
  std::vector<float> isolation;  // mean distance to the nearest neighbours, for ties
  std::vector<std::uint8_t> off_surface;  // the residual test's verdict (empty without it)
  std::vector<std::uint8_t> sparse_surface;  // low degree on a sparse surface (empty without)
  double spacing = 0.0;                      // the cloud's (RadiusDegrees::spacing)
  try
  {
    core::RadiusGraphParams params;
    params.radius = radius_;
    params.sigma = sigma_;
    params.radius_factor = kRadiusFactor;
    params.sigma_factor = kSigmaFactor;
    params.num_threads = num_threads_;
    if (gathered.surface_only > 0)
      params.query_rows = count;
    if (rule_ != OUTLIER_FRACTION)
      params.residual_multiplier = residual_multiplier_;
    if (rule_ == AUTOMATIC_THRESHOLD && keep_sparse_surfaces_)
      params.sparse_surface_ratio = automatic_ratio_;
    core::RadiusDegrees result = core::radiusGraphDegrees (gathered.xyz, params);
    used_radius_ = result.radius;
    used_sigma_ = result.sigma;
    spacing = result.spacing;
    degree = std::move (result.degree);
    isolation = std::move (result.mean_knn_distance);
    off_surface = std::move (result.off_surface);
    sparse_surface = std::move (result.sparse_surface);
    used_residual_scale_ = result.residual_scale;
  }
  catch (const std::exception &e)
  {
    PCL_ERROR ("[pcl_graph_denoise::%s::applyFilter] %s.\n", name.c_str (), e.what ());
    return fail (indices);
  }

  // Inlier flag of every gathered row, by the rule in force.
  std::vector<std::uint8_t> inlier (count, 1);
  if (rule_ == OUTLIER_FRACTION)
  {
    const auto removed = static_cast<std::size_t> (std::llround (outlier_fraction_ * double (count)));
    std::vector<std::size_t> by_degree (count);
    std::iota (by_degree.begin (), by_degree.end (), std::size_t (0));
    // Lowest degree first; among equal degrees (e.g. the many 0s of isolated points) the
    // more isolated first (larger mean distance to the nearest neighbours), then by row.
    std::stable_sort (by_degree.begin (), by_degree.end (), [&] (std::size_t a, std::size_t b) {
      return degree[a] < degree[b] || (degree[a] == degree[b] && isolation[a] > isolation[b]);
    });
    for (std::size_t r = 0; r < removed; ++r)
      inlier[by_degree[r]] = 0;
    used_threshold_ = removed < count ? degree[by_degree[removed]]
                                      : std::numeric_limits<double>::infinity ();
  }
  else
  {
    used_threshold_ = degree_threshold_;
    if (rule_ == AUTOMATIC_THRESHOLD)
    {
      const core::DegreeThreshold automatic = core::automaticDegreeThreshold (degree, automatic_ratio_);
      if (automatic.without_neighbour == count)
      {
        if (count > 1 && spacing > 0.0)  // else nothing to link: one position
          PCL_WARN ("[pcl_graph_denoise::%s::applyFilter] None of the %zu points has a "
                    "neighbour within epsilon = %g with a weight above 0 (theta = %g): no "
                    "degree threshold can be derived, and no point is removed for its "
                    "degree. Epsilon (setRadiusSearch) or theta (setSigma) is too small for "
                    "this cloud (the spacing of its points is %g).\n",
                    name.c_str (), count, used_radius_, used_sigma_, spacing);
      }
      else if (automatic.without_neighbour > 0)
        PCL_WARN ("[pcl_graph_denoise::%s::applyFilter] %zu of %zu points have no "
                  "neighbour within epsilon = %g: more than a quarter, so the automatic "
                  "threshold comes from the first quartile of the others' degrees.\n",
                  name.c_str (), automatic.without_neighbour, count, used_radius_);
      used_threshold_ = automatic.threshold;
    }
    for (std::size_t r = 0; r < count; ++r)
      inlier[r] = (degree[r] >= used_threshold_ || (!sparse_surface.empty () && sparse_surface[r])) &&
                  (off_surface.empty () || !off_surface[r]);
  }

  // Walk the caller's index list in its order: kept points to `indices`, the rest
  // (and every non-finite point) to the removed indices.
  std::vector<std::uint8_t> state (input_->size (), 0);  // 1 kept, 2 removed, 3 done
  for (std::size_t r = 0; r < count; ++r)
    state[gathered.cloud_index[r]] = (inlier[r] != 0) != negative_ ? 1 : 2;
  for (const auto index : gathered.non_finite)
    state[index] = 2;
  for (const auto index : gathered.far)
    state[index] = negative_ ? 1 : 2;
  // Into a list of their own: `indices` may be the caller's index list itself
  // (setIndices (list); filter (*list), which PCL's filters allow).
  pcl::Indices kept;
  kept.reserve (count);
  removed_indices_->clear ();
  for (const auto index : *indices_)
  {
    if (state[index] == 1)
      kept.push_back (index);
    else if (state[index] == 2 && extract_removed_indices_)
      removed_indices_->push_back (index);
    state[index] = 3;
  }
  indices.swap (kept);
}

} // namespace pcl_graph_denoise

#define PCL_INSTANTIATE_GraphDegreeOutlierRemoval(T)                                         \
  template class pcl_graph_denoise::GraphDegreeOutlierRemoval<T>;

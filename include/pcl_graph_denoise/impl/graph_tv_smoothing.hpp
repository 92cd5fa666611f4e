/*
 * pcl_graph_denoise: graph-signal-processing point cloud denoising for PCL.
 * SPDX-License-Identifier: BSD-3-Clause
 */
#pragma once

#include <pcl_graph_denoise/graph_tv_smoothing.h>
#include <pcl_graph_denoise/impl/graph_smoothing.hpp>

#include <memory>

namespace pcl_graph_denoise {

template <typename PointT>
typename GraphSmoothing<PointT>::Smoother
GraphTVSmoothing<PointT>::smoother (const core::PointGraph &graph, double gamma) const
{
  core::TotalVariationParams params;
  params.norm = norm_;
  params.tolerance = this->getTolerance ();
  params.max_iterations = this->max_iterations_;
  params.num_threads = this->num_threads_;
  params.progress = this->solverProgress ();
  auto system = std::make_shared<const core::TotalVariationSystem> (graph, gamma, params);
  return [system] (const core::Signal3 &f, core::SolverReport &report) {
    return system->solve (f, &report);
  };
}

template <typename PointT>
core::SmoothingKind
GraphTVSmoothing<PointT>::smoothingKind () const
{
  return core::SmoothingKind::TOTAL_VARIATION;
}

template <typename PointT>
double
GraphTVSmoothing<PointT>::automaticGamma (const core::PointGraph &graph, double noise) const
{
  return core::defaultTotalVariationGamma (graph, noise);
}

} // namespace pcl_graph_denoise

#define PCL_INSTANTIATE_GraphTVSmoothing(T)                                            \
  template class pcl_graph_denoise::GraphTVSmoothing<T>;

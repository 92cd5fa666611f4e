/*
 * pcl_graph_denoise: graph-signal-processing point cloud denoising for PCL.
 * SPDX-License-Identifier: BSD-3-Clause
 */
#pragma once

#include <pcl_graph_denoise/graph_tv_smoothing.h>
#include <pcl_graph_denoise/impl/graph_smoothing.hpp>

namespace pcl_graph_denoise {

template <typename PointT>
std::string
GraphTVSmoothing<PointT>::checkSolverParameters () const
{
  if (!(std::isfinite (params_.tolerance) && params_.tolerance > 0.0))
    return "tolerance (setTolerance) = " + std::to_string (params_.tolerance) +
           ": must be finite and > 0";
  if (params_.max_iterations < 1)
    return "maximum iterations (setMaximumIterations) = " +
           std::to_string (params_.max_iterations) + ": must be >= 1";
  return {};
}

template <typename PointT>
core::Signal3
GraphTVSmoothing<PointT>::smooth (const core::PointGraph &graph, const core::Signal3 &f,
                                        double gamma, core::SolverReport &report) const
{
  core::TotalVariationParams params = params_;
  params.num_threads = this->num_threads_;
  return core::solveTotalVariation (graph, f, gamma, params, &report);
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

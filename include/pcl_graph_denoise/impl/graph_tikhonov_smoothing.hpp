/*
 * pcl_graph_denoise: graph-signal-processing point cloud denoising for PCL.
 * SPDX-License-Identifier: BSD-3-Clause
 */
#pragma once

#include <pcl_graph_denoise/graph_tikhonov_smoothing.h>
#include <pcl_graph_denoise/impl/graph_smoothing.hpp>

#include <memory>

namespace pcl_graph_denoise {

template <typename PointT>
typename GraphSmoothing<PointT>::Smoother
GraphTikhonovSmoothing<PointT>::smoother (const core::PointGraph &graph, double gamma) const
{
  core::TikhonovParams params;
  params.solver = solver_;
  params.tolerance = this->getTolerance ();
  params.max_iterations = this->max_iterations_;
  params.num_threads = this->num_threads_;
  params.progress = this->solverProgress ();
  auto system = std::make_shared<const core::TikhonovSystem> (graph, gamma, params);
  return [system] (const core::Signal3 &f, core::SolverReport &report) {
    return system->solve (f, &report);
  };
}

template <typename PointT>
core::SmoothingKind
GraphTikhonovSmoothing<PointT>::smoothingKind () const
{
  return solver_ == core::TikhonovSolver::CHOLMOD ? core::SmoothingKind::TIKHONOV_CHOLMOD
                                                  : core::SmoothingKind::TIKHONOV;
}

template <typename PointT>
double
GraphTikhonovSmoothing<PointT>::automaticGamma (const core::PointGraph &graph, double noise) const
{
  return core::defaultTikhonovGamma (graph, noise);
}

} // namespace pcl_graph_denoise

#define PCL_INSTANTIATE_GraphTikhonovSmoothing(T)                                            \
  template class pcl_graph_denoise::GraphTikhonovSmoothing<T>;

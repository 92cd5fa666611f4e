/*
 * pcl_graph_denoise: graph-signal-processing point cloud denoising for PCL.
 * SPDX-License-Identifier: BSD-3-Clause
 */
#pragma once

/** \file noise_level.h
 *  \brief How noisy a point cloud is, measured on its graph: the basis of the
 *  data-derived smoothing strength. */

#include <pcl_graph_denoise/core/graph.h>

namespace pcl_graph_denoise {
namespace core {

/** \brief Robust estimate of the standard deviation of the points' noise along the
 *  local surface normal, in the points' units: the median over the vertices of the
 *  smallest principal standard deviation of the vertex, its graph neighbours and
 *  theirs (a local plane fit over two rings), scaled by sqrt(m / (m - 3)) for a neighbourhood of m points
 *  (three fitted parameters). Large clouds are sampled: at most 20,000 vertices,
 *  evenly along the graph's spatial order. `points` are in the graph's vertex order.
 *  Returns 0 for a graph without edges. */
double
estimateNoiseLevel (const PointGraph &graph, const Signal3 &points, int num_threads = 0);

} // namespace core
} // namespace pcl_graph_denoise

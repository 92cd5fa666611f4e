/*
 * pcl_graph_denoise: graph-signal-processing point cloud denoising for PCL.
 * SPDX-License-Identifier: BSD-3-Clause
 */
#pragma once

/* Private helper of the core: the connected components of a graph as a label per
 * vertex (the public summary is core::connectedComponents). */

#include <pcl_graph_denoise/core/graph.h>

#include <cstdint>
#include <vector>

namespace pcl_graph_denoise {
namespace core {
namespace detail {

/** For every vertex the smallest vertex of its connected component, counting only
 *  entries of positive weight (union-find, on `num_threads` threads, 0 = all); `linked`,
 *  when given, receives 1 for the vertices with at least one such entry. The labels are
 *  the same for any number of threads. Each edge is read from the row of its smaller
 *  vertex: the graph must be symmetric, as PointGraph is. */
std::vector<VertexIndex>
componentRoots (const PointGraph &graph, std::vector<std::uint8_t> *linked = nullptr,
                int num_threads = 0);

} // namespace detail
} // namespace core
} // namespace pcl_graph_denoise

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
 *  entries of positive weight (union-find); `linked`, when given, receives 1 for the
 *  vertices with at least one such entry. Serial: the same labels on any machine. */
std::vector<VertexIndex>
componentRoots (const PointGraph &graph, std::vector<std::uint8_t> *linked = nullptr);

} // namespace detail
} // namespace core
} // namespace pcl_graph_denoise

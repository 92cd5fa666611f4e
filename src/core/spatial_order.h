/*
 * pcl_graph_denoise: graph-signal-processing point cloud denoising for PCL.
 * SPDX-License-Identifier: BSD-3-Clause
 */
#pragma once

/* Private to the core: the spatially coherent vertex order of a PointGraph. */

#include <pcl_graph_denoise/core/graph.h>

namespace pcl_graph_denoise {
namespace core {
namespace detail {

/** Permutation that sorts the points along a Morton (Z-order) curve over their
 *  bounding box, up to 21 bits per axis; ties keep the input order. order[v] = input row.
 *  The result does not depend on the number of threads. */
std::vector<VertexIndex>
mortonOrder (const PointMatrix &points, int num_threads);

/** Rows of `points` taken in `order`. */
PointMatrix
reorderPoints (const PointMatrix &points, const std::vector<VertexIndex> &order);

} // namespace detail
} // namespace core
} // namespace pcl_graph_denoise

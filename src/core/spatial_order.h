/*
 * pcl_graph_denoise: graph-signal-processing point cloud denoising for PCL.
 * SPDX-License-Identifier: BSD-3-Clause
 */
#pragma once

/* Private to the core: the spatially coherent vertex order of a PointGraph. */

#include <pcl_graph_denoise/core/graph.h>

#include <cstdint>

namespace pcl_graph_denoise {
namespace core {
namespace detail {

/** The grid of a Morton (Z-order) curve: the points' bounding cube, anchored at `lo`,
 *  cut into 2^axis_bits cells per axis, `scale` cells per unit length. A point's code
 *  interleaves the bits of its cell's coordinates, x in bit 0 of every group of three;
 *  the top 3 l bits of a code name its cell at level l of the implicit octree (cells
 *  2^(axis_bits - l) fine cells wide), so points sorted by code lie cell by cell at
 *  every level. */
struct MortonGrid
{
  Eigen::Vector3d lo = Eigen::Vector3d::Zero ();
  double scale = 0.0;
  int axis_bits = 0;
};

/** A sort of the points along their Morton curve. */
struct MortonSort
{
  std::vector<VertexIndex> order;    ///< order[v] = input row of the v-th point
  std::vector<std::uint64_t> codes;  ///< codes[v] = code of that point, ascending
  MortonGrid grid;
};

/** Sorts the points along a Morton curve over their bounding box, up to 21 bits per
 *  axis; ties keep the input order. The result does not depend on the number of
 *  threads. Without `with_codes`, the codes are left empty. */
MortonSort
mortonSort (const PointMatrix &points, int num_threads, bool with_codes = true);

/** mortonSort's permutation alone. */
std::vector<VertexIndex>
mortonOrder (const PointMatrix &points, int num_threads);

/** The Morton code of cell coordinates (each below 2^21). */
std::uint64_t
interleave (std::uint64_t x, std::uint64_t y, std::uint64_t z);

/** The cell coordinate of axis `axis` (0, 1, 2) in a Morton code. */
std::uint64_t
deinterleave (std::uint64_t code, int axis);

/** Rows of `points` taken in `order`. */
PointMatrix
reorderPoints (const PointMatrix &points, const std::vector<VertexIndex> &order);

} // namespace detail
} // namespace core
} // namespace pcl_graph_denoise

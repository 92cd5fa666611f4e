/*
 * pcl_graph_denoise: graph-signal-processing point cloud denoising for PCL.
 * SPDX-License-Identifier: BSD-3-Clause
 */
#pragma once

/** \file operators.h
 *  \brief Linear operators of a PointGraph on signals with three columns:
 *  weighted degree, combinatorial Laplacian L = D - W, edge gradient and its adjoint.
 *
 *  Signals are indexed by vertex in the graph's internal order. Edges are numbered
 *  once each, as the entries (i, j) with i < j in CSR order; the gradient of a
 *  signal x on edge e = (i, j) is sqrt(w_ij) (x_i - x_j), so that
 *  |grad x|^2 = x^T L x and grad^T grad = L.
 */

#include <pcl_graph_denoise/core/graph.h>

namespace pcl_graph_denoise {
namespace core {

/** \brief Weighted degree d_i = sum_j w_ij of every vertex. */
std::vector<double>
weightedDegree (const PointGraph &graph, int num_threads = 0);

/** \brief y = L x with L = D - W, for an N x 3 signal x (y is resized). */
void
applyLaplacian (const PointGraph &graph, const Signal3 &x, Signal3 &y, int num_threads = 0);

/** \brief First edge number of each vertex's upper entries (j > i); N + 1 values,
 *  the last being the number of edges. Used to number edges in CSR order. */
std::vector<std::uint64_t>
edgeOffsets (const PointGraph &graph);

/** \brief g = grad x, one row per edge (E x 3, g is resized). */
void
applyGradient (const PointGraph &graph, const Signal3 &x, Signal3 &g, int num_threads = 0);

/** \brief x = grad^T g, the adjoint of applyGradient (N x 3, x is resized). */
void
applyGradientAdjoint (const PointGraph &graph, const Signal3 &g, Signal3 &x,
                      int num_threads = 0);

/** \brief How the graph falls apart: its connected components, counting only edges of
 *  positive weight (an edge whose Gaussian weight underflowed to 0 links nothing). The
 *  smoothing acts on each component on its own; an isolated vertex does not move. */
struct GraphComponents
{
  std::size_t count = 0;     ///< connected components (isolated vertices included)
  std::size_t isolated = 0;  ///< vertices without any edge of positive weight
  std::size_t largest = 0;   ///< vertices of the largest component
};

/** \brief The connected components of `graph` (union-find over its entries, on
 *  `num_threads` threads, 0 = all hardware threads; the same result for any number). */
GraphComponents
connectedComponents (const PointGraph &graph, int num_threads = 0);

} // namespace core
} // namespace pcl_graph_denoise

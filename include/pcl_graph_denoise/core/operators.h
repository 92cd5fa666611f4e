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

/** \brief The largest factor by which normalizeDensity scales a vertex's side of its edges
 *  (and the smallest is its inverse). */
constexpr double kDensityNormalizationLimit = 16.0;

/** \brief Divides the sampling density out of the graph's weights, in place: w_ij <- w_ij
 *  a_i a_j with a_i = (dbar / d_i)^power, d_i the weighted degree of vertex i and dbar the
 *  mean degree of the vertices with a link, dbar / d_i clamped to
 *  [1 / kDensityNormalizationLimit, kDensityNormalizationLimit]. With power 1 this is
 *  Coifman and Lafon's normalisation with alpha = 1 ("Diffusion maps", 2006), under which
 *  the random walk of the weights no longer depends on the sampling density. The
 *  Laplacian of the Gaussian weights smooths a vertex the more the higher its degree:
 *  the dense parts of an unevenly sampled surface (a scan's near part) far more than the
 *  sparse ones; with the degrees divided out, a vertex is smoothed the more the lower its
 *  degree was, which treats the sparse parts alike and, on an even sampling, pulls in the
 *  points that noise carried away from their neighbours. The weights stay symmetric (bit
 *  for bit), a weight of 0 stays 0 and a positive one positive; power 0, or a graph whose
 *  linked vertices all have one degree, leaves the weights as they are (the filters take
 *  the power from core::densityNormalizationPower). The result does
 *  not depend on the number of threads.
 *  \throws std::invalid_argument when power is not in [0, 1]. */
void
normalizeDensity (PointGraph &graph, double power = 1.0, int num_threads = 0);

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

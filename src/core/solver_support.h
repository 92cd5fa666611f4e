/*
 * pcl_graph_denoise: graph-signal-processing point cloud denoising for PCL.
 * SPDX-License-Identifier: BSD-3-Clause
 */
#pragma once

/* Private to the core: what the solvers share (checks, deterministic norms). */

#include <pcl_graph_denoise/core/graph.h>

#include "components.h"
#include "parallel.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <stdexcept>
#include <vector>

namespace pcl_graph_denoise {
namespace core {
namespace detail {

/** Each vertex's sum of sqrt(w_ij) over its stored entries: the row sums of |grad| of
 *  the total-variation term, behind TV's derived strength and its solver's steps. */
inline std::vector<double>
rootDegree (const PointGraph &graph, int num_threads = 0)
{
  std::vector<double> root_degree (graph.numVertices (), 0.0);
  parallelFor (root_degree.size (), num_threads, [&] (std::size_t begin, std::size_t end) {
    for (std::size_t i = begin; i < end; ++i)
      for (std::uint64_t e = graph.row_ptr[i]; e < graph.row_ptr[i + 1]; ++e)
        root_degree[i] += std::sqrt (double (graph.weight[e]));
  });
  return root_degree;
}

/** Three running sums (one per column), zero-initialised. */
struct Sum3
{
  double v[3] = {0.0, 0.0, 0.0};
  Sum3 &
  operator+= (const Sum3 &o)
  {
    for (int c = 0; c < 3; ++c)
      v[c] += o.v[c];
    return *this;
  }
};

/** Frobenius norm of an N x 3 signal, independent of the thread count. */
inline double
frobenius (const Signal3 &x, int num_threads)
{
  return std::sqrt (parallelSum<double> (static_cast<std::size_t> (x.rows ()), num_threads,
                                         [&] (std::size_t begin, std::size_t end) {
                                           double s = 0.0;
                                           for (std::size_t i = begin; i < end; ++i)
                                             s += x.row (i).squaredNorm ();
                                           return s;
                                         }));
}

/** Frobenius norm of x minus its column means. */
inline double
centredNorm (const Signal3 &x, int num_threads)
{
  const std::size_t n = static_cast<std::size_t> (x.rows ());
  if (n == 0)
    return 0.0;
  const Sum3 sum = parallelSum<Sum3> (n, num_threads, [&] (std::size_t begin, std::size_t end) {
    Sum3 s;
    for (std::size_t i = begin; i < end; ++i)
      for (int c = 0; c < 3; ++c)
        s.v[c] += x (i, c);
    return s;
  });
  const double mean[3] = {sum.v[0] / n, sum.v[1] / n, sum.v[2] / n};
  return std::sqrt (parallelSum<double> (n, num_threads, [&] (std::size_t begin, std::size_t end) {
    double s = 0.0;
    for (std::size_t i = begin; i < end; ++i)
      for (int c = 0; c < 3; ++c)
        s += (x (i, c) - mean[c]) * (x (i, c) - mean[c]);
    return s;
  }));
}

/** The scale of a solver's relative residual: the norm of f centred on the mean of each
 *  connected component of the graph (the solvers act on each component on its own, and
 *  keep its mean), but at most kRobustScaleCap times sqrt(n) times the median distance of
 *  the rows (a sample of about 20,000 of them, evenly spread) from their per-axis median.
 *  Centred on the whole cloud's mean instead, two clusters far apart made the scale as
 *  large as their distance, and the test stopped before either was solved (two spheres
 *  10^5 apart: no iteration at all). On a compact cloud the two measures agree within a
 *  factor of about 1.5 and the cap never applies; it bounds the scale where a few far
 *  points are linked to the rest. Where most rows coincide (a median distance of 0), the
 *  centred norm alone. */
constexpr double kRobustScaleCap = 4.0;

/** residualScale given the graph's components: `root` as componentRoots gives it, or empty
 *  for a graph of at most one component. */
inline double
residualScale (const std::vector<VertexIndex> &root, const Signal3 &f, int num_threads)
{
  const std::size_t n = static_cast<std::size_t> (f.rows ());
  if (n == 0)
    return 0.0;
  double centred = 0.0;
  if (root.empty ())
    centred = centredNorm (f, num_threads);
  else
  {
    // Each component's mean (kept at its root), then the rows' squares about it.
    std::vector<Eigen::Vector3d> sum (n, Eigen::Vector3d::Zero ());
    std::vector<std::size_t> size (n, 0);
    for (std::size_t i = 0; i < n; ++i)
    {
      sum[root[i]] += f.row (static_cast<Eigen::Index> (i)).transpose ();
      ++size[root[i]];
    }
    double squares = 0.0;
    for (std::size_t i = 0; i < n; ++i)
    {
      const std::size_t r = root[i];
      squares += (f.row (static_cast<Eigen::Index> (i)).transpose () - sum[r] / double (size[r]))
                     .squaredNorm ();
    }
    centred = std::sqrt (squares);
  }
  const std::size_t stride = std::max<std::size_t> (1, n / 20000);
  std::vector<double> values ((n + stride - 1) / stride);
  const auto middle = values.begin () + std::ptrdiff_t (values.size () / 2);
  Eigen::Vector3d median;
  for (int c = 0; c < 3; ++c)
  {
    for (std::size_t i = 0, s = 0; i < n; i += stride, ++s)
      values[s] = f (static_cast<Eigen::Index> (i), c);
    std::nth_element (values.begin (), middle, values.end ());
    median[c] = *middle;
  }
  for (std::size_t i = 0, s = 0; i < n; i += stride, ++s)
    values[s] = (f.row (static_cast<Eigen::Index> (i)).transpose () - median).norm ();
  std::nth_element (values.begin (), middle, values.end ());
  const double robust = kRobustScaleCap * std::sqrt (double (n)) * *middle;
  return robust > 0.0 ? std::min (centred, robust) : centred;  // 0: most rows coincide
}

/** The components of a graph as residualScale takes them: componentRoots, or empty when
 *  there is at most one. */
inline std::vector<VertexIndex>
residualComponents (const PointGraph &graph, int num_threads)
{
  std::vector<VertexIndex> root = componentRoots (graph, nullptr, num_threads);
  std::size_t components = 0;
  for (std::size_t i = 0; i < root.size () && components <= 1; ++i)
    components += root[i] == i;
  if (components <= 1)
    root.clear ();
  return root;
}

/** The solvers' checks of their settings; throws std::invalid_argument. */
inline void
requireSolverSettings (double gamma, int num_threads, double tolerance, int max_iterations)
{
  if (!(std::isfinite (tolerance) && tolerance > 0.0))
    throw std::invalid_argument ("tolerance must be finite and > 0");
  if (max_iterations < 0)
    throw std::invalid_argument ("max_iterations must be >= 0");
  if (!(std::isfinite (gamma) && gamma >= 0.0))
    throw std::invalid_argument ("gamma must be finite and >= 0");
  if (num_threads < 0)
    throw std::invalid_argument ("num_threads must be >= 0");
}

/** The solvers' checks of a signal; throws std::invalid_argument. */
inline void
requireSolverSignal (const PointGraph &graph, const Signal3 &f)
{
  if (static_cast<std::size_t> (f.rows ()) != graph.numVertices ())
    throw std::invalid_argument ("the signal has the wrong number of rows");
  if (!f.allFinite ())
    throw std::invalid_argument ("the signal must be finite");
}

/** Throws std::runtime_error when a solver's result is not finite, or lies farther
 *  outside the bounding box of its input f than that box's largest side in some
 *  coordinate: a gamma so large that the computation overflowed or lost its precision
 *  (at gamma 1e20 on a unit sphere, conjugate gradients wandered to 150 units, at 1e30 to
 *  1e11). Both solvers' exact solutions lie in the box: (I + 2 gamma L)^-1 has no negative
 *  entry and rows summing to 1, and clamping a point to the box lowers both terms of the
 *  total-variation objective. Nothing non-finite or that far off leaves a solver. */
inline void
requireSaneResult (const Signal3 &x, const Signal3 &f, double gamma, const char *solver)
{
  char text[300];
  if (!x.allFinite ())
  {
    std::snprintf (text, sizeof (text),
                   "the %s solution overflowed: gamma = %g is too large for the precision of "
                   "the computation",
                   solver, gamma);
    throw std::runtime_error (text);
  }
  if (f.rows () == 0)
    return;
  const Eigen::RowVector3d lo = f.colwise ().minCoeff (), hi = f.colwise ().maxCoeff ();
  const double side = (hi - lo).maxCoeff ();
  const Eigen::RowVector3d x_lo = x.colwise ().minCoeff (), x_hi = x.colwise ().maxCoeff ();
  if (((lo - x_lo).array () <= side).all () && ((x_hi - hi).array () <= side).all ())
    return;
  std::snprintf (text, sizeof (text),
                 "the %s solver lost its precision: its result lies outside the input's "
                 "bounding box by more than the box's size, where the exact solution lies "
                 "inside it; gamma = %g is too large for the precision of the computation",
                 solver, gamma);
  throw std::runtime_error (text);
}

} // namespace detail
} // namespace core
} // namespace pcl_graph_denoise

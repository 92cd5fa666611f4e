/*
 * pcl_graph_denoise: graph-signal-processing point cloud denoising for PCL.
 * SPDX-License-Identifier: BSD-3-Clause
 */
#include <pcl_graph_denoise/core/operators.h>
#include <pcl_graph_denoise/core/solvers.h>

#include "huge_pages.h"
#include "parallel.h"
#include "solver_support.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <stdexcept>

namespace pcl_graph_denoise {
namespace core {

/*
 * The dual variable lives on the stored CSR entries: y(i, j) for every entry, kept
 * antisymmetric, y(j, i) = -y(i, j), so that each undirected edge has one dual value
 * and the adjoint of the gradient at vertex i reads only row i:
 *   (grad^T y)_i = sum_j sqrt(w_ij) y(i, j).
 * The dual update y(i, j) <- proj(y(i, j) + s sqrt(w_ij) (xbar_i - xbar_j)) is odd in
 * (i, j) and the projections are odd, so antisymmetry holds exactly in floating point
 * with every row updated independently (parallel, thread-count independent).
 */

namespace {

/** The duals, one array per coordinate (column-major), so that the update of a row's
 *  entries runs over consecutive floats. */
using Duals = Eigen::Matrix<float, Eigen::Dynamic, 3, Eigen::ColMajor>;

/** A row's entries are updated a batch at a time: their differences gathered first,
 *  then the dual step and the projection over the batch as over plain arrays (vectorised:
 *  the file is compiled without errno and trap semantics for it), then the row's adjoint
 *  summed in entry order. */
constexpr std::size_t kDualBatch = 32;

/** Dual ascent and projection of `count` consecutive entries, y <- proj(y + step d) onto
 *  the dual ball of radius gamma of the norm (odd in y and d, so antisymmetry holds
 *  exactly). The isotropic shrink factor is computed for every entry and applied where
 *  the ball is left, without a branch; an entry inside keeps its value (times 1). */
inline void
dualStep (float *y0, float *y1, float *y2, const float (&d)[3][kDualBatch], std::size_t count,
          float step, float gamma, TotalVariationNorm norm)
{
  if (norm == TotalVariationNorm::ISOTROPIC)
  {
    const float gamma2 = gamma * gamma;
    for (std::size_t t = 0; t < count; ++t)
    {
      const float v0 = y0[t] + step * d[0][t];
      const float v1 = y1[t] + step * d[1][t];
      const float v2 = y2[t] + step * d[2][t];
      const float squared = v0 * v0 + v1 * v1 + v2 * v2;
      const float shrink = gamma / std::sqrt (squared);
      const float scale = squared > gamma2 ? shrink : 1.0f;
      y0[t] = v0 * scale;
      y1[t] = v1 * scale;
      y2[t] = v2 * scale;
    }
  }
  else
  {
    float *y[3] = {y0, y1, y2};
    for (int c = 0; c < 3; ++c)
      for (std::size_t t = 0; t < count; ++t)
        y[c][t] = std::max (-gamma, std::min (gamma, y[c][t] + step * d[c][t]));
  }
}

/** TV(x) = 1/2 sum over stored entries of the norm of sqrt(w) (x_i - x_j). A block's
 *  entries are taken a batch at a time, their differences gathered first and their norms
 *  computed over the batch (vectorised), then summed in entry order. */
double
totalVariation (const PointGraph &graph, const Signal3 &x, TotalVariationNorm norm,
                int num_threads)
{
  return 0.5 * detail::parallelSum<double> (
                   graph.numVertices (), num_threads, [&] (std::size_t begin, std::size_t end) {
                     double sum = 0.0;
                     double d[3][kDualBatch], length[kDualBatch];
                     std::size_t i = begin;
                     const std::uint64_t last = graph.row_ptr[end];
                     for (std::uint64_t first = graph.row_ptr[begin]; first < last;
                          first += kDualBatch)
                     {
                       const std::size_t count = static_cast<std::size_t> (
                           std::min<std::uint64_t> (kDualBatch, last - first));
                       for (std::size_t t = 0; t < count; ++t)
                       {
                         while (first + t >= graph.row_ptr[i + 1])
                           ++i;
                         const VertexIndex j = graph.col[first + t];
                         for (int c = 0; c < 3; ++c)
                           d[c][t] = x (i, c) - x (j, c);
                       }
                       const float *weight = graph.weight.data () + first;
                       if (norm == TotalVariationNorm::ISOTROPIC)
                         for (std::size_t t = 0; t < count; ++t)
                         {
                           const double s = std::sqrt (double (weight[t]));
                           const double d0 = s * d[0][t], d1 = s * d[1][t], d2 = s * d[2][t];
                           length[t] = std::sqrt (d0 * d0 + d1 * d1 + d2 * d2);
                         }
                       else
                         for (std::size_t t = 0; t < count; ++t)
                         {
                           const double s = std::sqrt (double (weight[t]));
                           length[t] = std::abs (s * d[0][t]) + std::abs (s * d[1][t]) +
                                       std::abs (s * d[2][t]);
                         }
                       for (std::size_t t = 0; t < count; ++t)
                         sum += length[t];
                     }
                     return sum;
                   });
}

} // namespace

double
totalVariationObjective (const PointGraph &graph, const Signal3 &f, const Signal3 &x,
                         double gamma, TotalVariationNorm norm)
{
  if (f.rows () != x.rows () || static_cast<std::size_t> (x.rows ()) != graph.numVertices ())
    throw std::invalid_argument ("totalVariationObjective: signals of the wrong size");
  return 0.5 * (x - f).squaredNorm () + gamma * totalVariation (graph, x, norm, 0);
}

Signal3
solveTotalVariation (const PointGraph &graph, const Signal3 &f, double gamma,
                     const TotalVariationParams &params, SolverReport *report)
{
  detail::requireSolverInput (graph, f, gamma, params.num_threads, params.tolerance,
                              params.max_iterations);

  SolverReport local;
  SolverReport &out = report ? *report : local;
  out = SolverReport{};
  const std::size_t n = graph.numVertices ();
  const int threads = params.num_threads;
  if (gamma == 0.0 || graph.numEntries () == 0)
  {
    out.converged = true;
    return f;
  }
  // The duals are single precision and bounded by gamma.
  if (!(gamma <= double (std::numeric_limits<float>::max ())))
  {
    char text[160];
    std::snprintf (text, sizeof (text),
                   "gamma = %g is too large for the total-variation solver, whose duals are "
                   "single precision: must be at most %g",
                   gamma, double (std::numeric_limits<float>::max ()));
    throw std::invalid_argument (text);
  }

  // Diagonal preconditioning (Pock and Chambolle 2011, alpha = 1): each vertex's primal
  // step is the inverse of its row sum of |grad|, tau_i = 1 / sum_j sqrt(w_ij), and each
  // entry's dual step sigma_e = 1 / (2 sqrt(w_e)), so that sigma_e sqrt(w_e) = 1/2 and the
  // dual update needs no weight. A global `scale` multiplies the primal steps and
  // divides the dual ones, shrunk as in Chambolle and Pock's accelerated algorithm 2 with
  // the data term's modulus of strong convexity in the preconditioned metric, the
  // smallest tau (with the mean tau instead, the fountain scan's weakly linked pieces
  // diverged). On noisy spheres this halves the iterations at strong smoothing.
  const float bound_gamma = static_cast<float> (gamma);
  std::vector<float> root_weight;
  detail::resizeOnHugePages (root_weight, graph.numEntries ());
  detail::parallelFor (root_weight.size (), threads, [&] (std::size_t begin, std::size_t end) {
    for (std::size_t e = begin; e < end; ++e)
      root_weight[e] = std::sqrt (graph.weight[e]);
  });
  std::vector<double> tau = detail::rootDegree (graph, threads);
  double min_tau = std::numeric_limits<double>::infinity ();
  for (double &t : tau)
  {
    t = t > 0.0 ? 1.0 / t : 0.0;
    if (t > 0.0)
      min_tau = std::min (min_tau, t);
  }
  if (!std::isfinite (min_tau))  // no vertex with a weighted edge
  {
    out.converged = true;
    return f;
  }
  double scale = 1.0;

  // Warm start: every edge difference of a point cloud is non-zero, so nearly every
  // dual ends on the boundary of its ball, along the edge's difference. Starting the
  // duals there for the differences of f (feasible, and odd in (i, j) as required)
  // and the primal at f - grad^T y cuts the iterations several times.
  const auto rows = static_cast<Eigen::Index> (n);
  Signal3 x = detail::matrixOnHugePages<Signal3> (rows);
  Signal3 xbar = detail::matrixOnHugePages<Signal3> (rows);
  Signal3 gty = detail::matrixOnHugePages<Signal3> (rows);
  Duals y = detail::matrixOnHugePages<Duals> (static_cast<Eigen::Index> (graph.numEntries ()));
  const auto warmStart = [&] () {
    detail::parallelFor (n, threads, [&] (std::size_t begin, std::size_t end) {
      for (std::size_t i = begin; i < end; ++i)
      {
        double acc[3] = {0.0, 0.0, 0.0};
        for (std::uint64_t e = graph.row_ptr[i]; e < graph.row_ptr[i + 1]; ++e)
        {
          const VertexIndex j = graph.col[e];
          const double d[3] = {f (i, 0) - f (j, 0), f (i, 1) - f (j, 1), f (i, 2) - f (j, 2)};
          const double length = std::sqrt (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
          float v[3];
          for (int c = 0; c < 3; ++c)
          {
            if (params.norm == TotalVariationNorm::ISOTROPIC)
              v[c] = length > 0.0 ? static_cast<float> (gamma * d[c] / length) : 0.0f;
            else
              v[c] = d[c] > 0.0 ? bound_gamma : (d[c] < 0.0 ? -bound_gamma : 0.0f);
          }
          for (int c = 0; c < 3; ++c)
          {
            y (e, c) = v[c];
            acc[c] += double (root_weight[e]) * double (v[c]);
          }
        }
        for (int c = 0; c < 3; ++c)
          x (i, c) = xbar (i, c) = f (i, c) - acc[c];
      }
    });
  };
  warmStart ();
  // With a gamma large against the cloud's differences the minimiser is nearly constant
  // and that start lies far from it (about gamma times the degree): then the cold start,
  // duals 0 and x = f, when the warm start's objective is more than kColdStart times
  // f's. (At the filters' derived gammas the ratio is 1-7 on noisy spheres and cubes,
  // where the warm start still converges faster and lands closer to the surface.)
  constexpr double kColdStart = 100.0;
  const double warm_objective =
      0.5 * (x - f).squaredNorm () + gamma * totalVariation (graph, x, params.norm, threads);
  const double cold_objective = gamma * totalVariation (graph, f, params.norm, threads);
  const bool warm = warm_objective <= kColdStart * cold_objective;
  if (!warm)
  {
    y.setZero ();
    x = f;
    xbar = f;
  }
  const double start_objective = std::min (warm_objective, cold_objective);
  const double f_norm2 = f.squaredNorm ();

  // The gap is checked after kFirstChecks and 2 kFirstChecks iterations, then at most
  // kCheckInterval iterations apart: once it falls between two checks, the next comes
  // when that rate of fall would bring it to the tolerance (one iteration on at the
  // least). The solve stops within about an iteration of meeting the tolerance, not up to
  // nine iterations after as with a check every 10 (about as many checks: one more).
  constexpr int kFirstChecks = 5, kCheckInterval = 10;
  int next_check = kFirstChecks, last_check = 0;
  double last_residual = std::numeric_limits<double>::infinity ();
  int it = 0;
  double gap = std::numeric_limits<double>::infinity ();
  double last_objective = start_objective;  // the primal objective at the last check
  while (it < params.max_iterations)
  {
    // Dual ascent with projection, then the adjoint of each row, fused per row. The
    // dual is stored and updated in single precision (the edge differences are small
    // numbers of similar size); sums over a row are accumulated in double.
    const float step = static_cast<float> (0.5 / scale);
    detail::parallelFor (n, threads, [&] (std::size_t begin, std::size_t end) {
      float d[3][kDualBatch];
      for (std::size_t i = begin; i < end; ++i)
      {
        double acc[3] = {0.0, 0.0, 0.0};
        for (std::uint64_t first = graph.row_ptr[i]; first < graph.row_ptr[i + 1];
             first += kDualBatch)
        {
          const std::size_t count = static_cast<std::size_t> (
              std::min<std::uint64_t> (kDualBatch, graph.row_ptr[i + 1] - first));
          for (std::size_t t = 0; t < count; ++t)
          {
            const VertexIndex j = graph.col[first + t];
            for (int c = 0; c < 3; ++c)
              d[c][t] = static_cast<float> (xbar (i, c) - xbar (j, c));
          }
          const auto e = static_cast<Eigen::Index> (first);
          dualStep (&y (e, 0), &y (e, 1), &y (e, 2), d, count, step, bound_gamma, params.norm);
          for (std::size_t t = 0; t < count; ++t)
            for (int c = 0; c < 3; ++c)
              acc[c] += double (root_weight[first + t]) * double (y (e + t, c));
        }
        for (int c = 0; c < 3; ++c)
          gty (i, c) = acc[c];
      }
    });
    // Primal step: prox of 1/2 |x - f|^2, then the accelerated extrapolation.
    const double theta = 1.0 / std::sqrt (1.0 + 2.0 * scale * min_tau);
    detail::parallelFor (n, threads, [&] (std::size_t begin, std::size_t end) {
      for (std::size_t i = begin; i < end; ++i)
      {
        const double step_i = scale * tau[i];
        for (int c = 0; c < 3; ++c)
        {
          const double previous = x (i, c);
          const double next = (previous - step_i * gty (i, c) + step_i * f (i, c)) / (1.0 + step_i);
          x (i, c) = next;
          xbar (i, c) = next + theta * (next - previous);
        }
      }
    });
    scale *= theta;
    ++it;

    // Duality gap at the checks and at the cap: P(x) - D(y), with
    // D(y) = <f, grad^T y> - 1/2 |grad^T y|^2 (y is feasible after the projection).
    if (it == next_check || it == params.max_iterations)
    {
      // |x - f|^2, <f, grad^T y> and |grad^T y|^2 in one parallel pass.
      struct Terms
      {
        double data = 0.0, cross = 0.0, adjoint = 0.0;
        Terms &
        operator+= (const Terms &o)
        {
          data += o.data;
          cross += o.cross;
          adjoint += o.adjoint;
          return *this;
        }
      };
      const Terms terms = detail::parallelSum<Terms> (n, threads, [&] (std::size_t begin, std::size_t end) {
        Terms t;
        for (std::size_t i = begin; i < end; ++i)
          for (int c = 0; c < 3; ++c)
          {
            t.data += (x (i, c) - f (i, c)) * (x (i, c) - f (i, c));
            t.cross += f (i, c) * gty (i, c);
            t.adjoint += gty (i, c) * gty (i, c);
          }
        return t;
      });
      const double primal =
          0.5 * terms.data + gamma * totalVariation (graph, x, params.norm, threads);
      last_objective = primal;
      const double dual = terms.cross - 0.5 * terms.adjoint;
      gap = primal - dual;
      // The floor: with a gamma so small that the objective is below the rounding of x
      // in double, the gap measures only that rounding and never meets the tolerance.
      // Stopping there leaves x within sqrt(2 tolerance) 1e-10 |f| of the minimiser
      // (the objective is 1-strongly convex): nothing a float output can show.
      const double scale = std::max (primal, 1e-20 * f_norm2);
      out.residual = gap / scale;
      if (params.progress)
        params.progress (it, out.residual);
      if (gap <= params.tolerance * scale)
      {
        out.converged = true;
        break;
      }
      int interval = last_check > 0 ? kCheckInterval : kFirstChecks;
      if (last_check > 0 && out.residual < last_residual && out.residual > 0.0)
      {
        const double rate = std::log (out.residual / last_residual) / double (it - last_check);
        const double needed = std::log (params.tolerance / out.residual) / rate;
        if (needed < double (kCheckInterval))  // also false when not finite
          interval = std::max (1, static_cast<int> (std::ceil (needed)));
      }
      last_check = it;
      last_residual = out.residual;
      next_check = it + interval;
    }
  }
  out.iterations = it;
  // Stopped short, and worse than it started (or not finite): the start is the best
  // iterate known.
  if (!out.converged && !(last_objective <= start_objective))
  {
    if (warm)
      warmStart ();
    else
      x = f;
  }
  detail::requireSaneResult (x, f, gamma, "total-variation");
  return x;
}

} // namespace core
} // namespace pcl_graph_denoise

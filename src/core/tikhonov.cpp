/*
 * pcl_graph_denoise: graph-signal-processing point cloud denoising for PCL.
 * SPDX-License-Identifier: BSD-3-Clause
 */
#include <pcl_graph_denoise/core/operators.h>
#include <pcl_graph_denoise/core/solvers.h>

#include "cholmod_solver.h"
#include "parallel.h"
#include "solver_support.h"

#include <cmath>
#include <stdexcept>

namespace pcl_graph_denoise {
namespace core {

namespace {

/** Jacobi-preconditioned conjugate gradient on (I + 2 gamma L), one scalar step size per
 *  column, the three columns fused in each pass over the graph. */
Signal3
conjugateGradient (const PointGraph &graph, const Signal3 &f, double gamma,
                   const TikhonovParams &params, SolverReport &report)
{
  const std::size_t n = graph.numVertices ();
  const int threads = params.num_threads;
  const double g2 = 2.0 * gamma;
  const std::vector<double> degree = weightedDegree (graph, threads);

  // A p for the current direction, with the column dot products p . A p.
  auto applyA = [&] (const Signal3 &p, Signal3 &q) {
    return detail::parallelSum<detail::Sum3> (n, threads, [&] (std::size_t begin, std::size_t end) {
      detail::Sum3 pq;
      for (std::size_t i = begin; i < end; ++i)
      {
        double a[3] = {0.0, 0.0, 0.0};
        for (std::uint64_t e = graph.row_ptr[i]; e < graph.row_ptr[i + 1]; ++e)
        {
          const double w = graph.weight[e];
          const VertexIndex j = graph.col[e];
          for (int c = 0; c < 3; ++c)
            a[c] += w * (p (i, c) - p (j, c));
        }
        for (int c = 0; c < 3; ++c)
        {
          q (i, c) = p (i, c) + g2 * a[c];
          pq.v[c] += p (i, c) * q (i, c);
        }
      }
      return pq;
    });
  };

  const double scale = detail::residualScale (graph, f, threads);
  // The Jacobi preconditioner's diagonal; its product with r is taken where it is used
  // rather than stored (one array fewer to write and read back per iteration: the loop
  // is bound by memory traffic).
  std::vector<double> inverse_diagonal (n);
  detail::parallelFor (n, threads, [&] (std::size_t begin, std::size_t end) {
    for (std::size_t i = begin; i < end; ++i)
      inverse_diagonal[i] = 1.0 / (1.0 + g2 * degree[i]);
  });
  Signal3 x = f, r (n, 3), p (n, 3), q (n, 3);
  // r = f - A f = -2 gamma L f.
  applyA (x, q);
  r = f - q;
  // The squared norm of r and the dot products r . z with its preconditioned copy z.
  struct Residual
  {
    double rr = 0.0;
    detail::Sum3 rz;
    Residual &
    operator+= (const Residual &o)
    {
      rr += o.rr;
      rz += o.rz;
      return *this;
    }
  };
  const auto sumRow = [&] (std::size_t i, Residual &sums) {
    const double m = inverse_diagonal[i];
    for (int c = 0; c < 3; ++c)
    {
      sums.rr += r (i, c) * r (i, c);
      sums.rz.v[c] += r (i, c) * (m * r (i, c));
    }
  };
  Residual sums = detail::parallelSum<Residual> (n, threads, [&] (std::size_t begin, std::size_t end) {
    Residual partial;
    for (std::size_t i = begin; i < end; ++i)
    {
      sumRow (i, partial);
      for (int c = 0; c < 3; ++c)
        p (i, c) = inverse_diagonal[i] * r (i, c);
    }
    return partial;
  });
  detail::Sum3 rz = sums.rz;
  double residual = std::sqrt (sums.rr);
  report.residual = scale > 0.0 ? residual / scale : 0.0;
  report.converged = residual <= params.tolerance * scale;
  int it = 0;
  while (!report.converged && it < params.max_iterations)
  {
    const detail::Sum3 pq = applyA (p, q);
    double alpha[3];
    for (int c = 0; c < 3; ++c)
      alpha[c] = pq.v[c] > 0.0 ? rz.v[c] / pq.v[c] : 0.0;
    // The step and the new residual's sums in one pass.
    sums = detail::parallelSum<Residual> (n, threads, [&] (std::size_t begin, std::size_t end) {
      Residual partial;
      for (std::size_t i = begin; i < end; ++i)
      {
        for (int c = 0; c < 3; ++c)
        {
          x (i, c) += alpha[c] * p (i, c);
          r (i, c) -= alpha[c] * q (i, c);
        }
        sumRow (i, partial);
      }
      return partial;
    });
    residual = std::sqrt (sums.rr);
    ++it;
    report.residual = scale > 0.0 ? residual / scale : 0.0;
    report.converged = residual <= params.tolerance * scale;
    if (params.progress && it % 10 == 0)
      params.progress (it, report.residual);
    if (report.converged)
      break;
    double beta[3];
    for (int c = 0; c < 3; ++c)
      beta[c] = rz.v[c] > 0.0 ? sums.rz.v[c] / rz.v[c] : 0.0;
    rz = sums.rz;
    detail::parallelFor (n, threads, [&] (std::size_t begin, std::size_t end) {
      for (std::size_t i = begin; i < end; ++i)
      {
        const double m = inverse_diagonal[i];
        for (int c = 0; c < 3; ++c)
          p (i, c) = m * r (i, c) + beta[c] * p (i, c);
      }
    });
  }
  report.iterations = it;
  return x;
}

} // namespace

Signal3
solveTikhonov (const PointGraph &graph, const Signal3 &f, double gamma,
               const TikhonovParams &params, SolverReport *report)
{
  detail::requireSolverInput (graph, f, gamma, params.num_threads, params.tolerance,
                              params.max_iterations);

  SolverReport local;
  SolverReport &out = report ? *report : local;
  out = SolverReport{};
  if (gamma == 0.0 || graph.numEntries () == 0)
  {
    out.converged = true;
    return f;
  }
  if (params.solver == TikhonovSolver::CHOLMOD)
  {
    Signal3 x = detail::solveTikhonovCholmod (graph, f, gamma);
    detail::requireSaneResult (x, f, gamma, "Tikhonov (CHOLMOD)");
    out.converged = true;
    out.iterations = 1;
    Signal3 lx;
    applyLaplacian (graph, x, lx, params.num_threads);
    const double scale = detail::residualScale (graph, f, params.num_threads);
    out.residual = scale > 0.0 ? (x + 2.0 * gamma * lx - f).norm () / scale : 0.0;
    return x;
  }
  Signal3 x = conjugateGradient (graph, f, gamma, params, out);
  detail::requireSaneResult (x, f, gamma, "Tikhonov");
  return x;
}

} // namespace core
} // namespace pcl_graph_denoise

/*
 * pcl_graph_denoise: graph-signal-processing point cloud denoising for PCL.
 * SPDX-License-Identifier: BSD-3-Clause
 */
#include <pcl_graph_denoise/core/operators.h>
#include <pcl_graph_denoise/core/solvers.h>

#include "aggregation.h"
#include "cholmod_solver.h"
#include "huge_pages.h"
#include "parallel.h"
#include "solver_support.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

namespace pcl_graph_denoise {
namespace core {

namespace {

using detail::AggregationPreconditioner;

/** The single-precision phase of the conjugate gradient stops once its residual is this
 *  many times below the one it started from, also when the tolerance lies lower: single
 *  precision takes a residual about that far down whatever the system, and the phase in
 *  double precision, started from its result, takes it the rest of the way. */
constexpr double kSinglePrecisionReach = 1e-5;

/** Rows per task of the passes that also sum the residual over the preconditioner's
 *  aggregates: a multiple of the aggregate, so that no aggregate spans two tasks. */
constexpr std::size_t kRowsPerTask = 4096;
static_assert (kRowsPerTask % AggregationPreconditioner::kFirstAggregate == 0,
               "an aggregate must lie within one task");

/** The coarse levels serve a phase in Scalar only where 2 gamma times the largest degree,
 *  times the Scalar's epsilon, is at most this: the product (1 + 2 gamma d_i) p_i -
 *  2 gamma sum_j w_ij p_j cancels to about p_i on the smooth directions the coarse levels
 *  add, and loses that many times p_i to rounding (a single-precision phase thus up to
 *  2 gamma d of about 1.7e5, far above the filters' defaults; beyond, Jacobi alone). */
constexpr double kCoarseReach = 1e-2;

template <typename Scalar>
using Columns3 = Eigen::Matrix<Scalar, Eigen::Dynamic, 3, Eigen::RowMajor>;

/** r = f - (I + 2 gamma L) x in double precision; returns its Frobenius norm. */
double
trueResidual (const PointGraph &graph, const Signal3 &f, const Signal3 &x, double g2,
              int threads, Signal3 &r)
{
  if (r.rows () != x.rows ())
    r = detail::matrixOnHugePages<Signal3> (x.rows ());
  applyLaplacian (graph, x, r, threads);
  r = f - x - g2 * r;
  return detail::frobenius (r, threads);
}

/** Preconditioned conjugate gradient on (I + 2 gamma L) d = r for a correction d, added
 *  to x at the end: the preconditioner z = D^-1 r + P V (P^T r), Jacobi plus the coarse
 *  levels' V-cycle (aggregation.h), whose restriction P^T r is summed in the pass that
 *  updates r and whose share of r . z is rc . zc on the coarse level; one scalar step
 *  size per column, the three columns fused in each pass over the graph, the vectors
 *  stored in Scalar (single precision halves the memory traffic that bounds the loop)
 *  and every sum accumulated in double. The product is taken as (1 + 2 gamma d_i) p_i -
 *  2 gamma sum_j w_ij p_j. Stops once the recursive residual is at most `target` or after
 *  `max_iterations`; `done` iterations came before (for the progress reports). Returns
 *  the iterations run. */
template <typename Scalar>
int
correct (const PointGraph &graph, double g2, const std::vector<double> &degree,
         const AggregationPreconditioner &coarse, const Signal3 &r0, double target,
         int max_iterations, int done, const TikhonovParams &params, double scale, Signal3 &x)
{
  using Coarse3 = AggregationPreconditioner::Coarse3;
  constexpr std::size_t kAggregate = AggregationPreconditioner::kFirstAggregate;
  const std::size_t n = graph.numVertices ();
  const int threads = params.num_threads;
  const Scalar g2s = static_cast<Scalar> (g2);
  // The diagonal and its inverse (the Jacobi preconditioner, applied where it is used
  // rather than stored with r: one array fewer to write and read back per iteration).
  std::vector<Scalar> diagonal, inverse;
  detail::resizeOnHugePages (diagonal, n);
  detail::resizeOnHugePages (inverse, n);
  detail::parallelFor (n, threads, [&] (std::size_t begin, std::size_t end) {
    for (std::size_t i = begin; i < end; ++i)
    {
      diagonal[i] = static_cast<Scalar> (1.0 + g2 * degree[i]);
      inverse[i] = static_cast<Scalar> (1.0 / (1.0 + g2 * degree[i]));
    }
  });
  const auto rows = static_cast<Eigen::Index> (n);
  Columns3<Scalar> d = detail::matrixOnHugePages<Columns3<Scalar>> (rows);
  Columns3<Scalar> r = detail::matrixOnHugePages<Columns3<Scalar>> (rows);
  Columns3<Scalar> p = detail::matrixOnHugePages<Columns3<Scalar>> (rows);
  Columns3<Scalar> q = detail::matrixOnHugePages<Columns3<Scalar>> (rows);
  d.setZero ();
  r = r0.template cast<Scalar> ();
  Coarse3 rc = Coarse3::Zero (static_cast<Eigen::Index> (coarse.coarseSize ()), 3), zc;
  const std::vector<std::uint8_t> &linked = coarse.linked ();
  const double max_degree = *std::max_element (degree.begin (), degree.end ());
  const bool use_coarse =
      g2 * max_degree * std::numeric_limits<Scalar>::epsilon () <= kCoarseReach;
  zc.setZero (rc.rows (), 3);

  // q = A p, with the column dot products p . A p.
  auto applyA = [&] () {
    return detail::parallelSum<detail::Sum3> (n, threads, [&] (std::size_t begin, std::size_t end) {
      detail::Sum3 pq;
      for (std::size_t i = begin; i < end; ++i)
      {
        Scalar a[3] = {0, 0, 0};
        for (std::uint64_t e = graph.row_ptr[i]; e < graph.row_ptr[i + 1]; ++e)
        {
          const Scalar w = graph.weight[e];
          const VertexIndex j = graph.col[e];
          for (int c = 0; c < 3; ++c)
            a[c] += w * p (j, c);
        }
        for (int c = 0; c < 3; ++c)
        {
          q (i, c) = diagonal[i] * p (i, c) - g2s * a[c];
          pq.v[c] += double (p (i, c)) * double (q (i, c));
        }
      }
      return pq;
    });
  };
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
  // Row i's share of the sums, and of its aggregate's restricted residual (tasks of
  // kRowsPerTask rows: each aggregate within one).
  const auto sumRow = [&] (std::size_t i, Residual &sums) {
    const double m = inverse[i];
    const std::size_t a = i / kAggregate;
    if (i % kAggregate == 0)
      rc.row (a).setZero ();
    for (int c = 0; c < 3; ++c)
    {
      const double ri = r (i, c);
      sums.rr += ri * ri;
      sums.rz.v[c] += ri * (m * ri);
      if (linked[i])
        rc (a, c) += ri;
    }
  };
  // zc from rc, and its share of r . z.
  const auto coarseCorrection = [&] (detail::Sum3 &rz) {
    if (!use_coarse)
      return;
    coarse.applyCoarse (rc, zc);
    for (int c = 0; c < 3; ++c)
      rz.v[c] += rc.col (c).dot (zc.col (c));
  };
  // p = D^-1 r + P zc + beta p.
  const auto updateDirection = [&] (const Scalar *beta) {
    detail::parallelFor (n, threads, [&] (std::size_t begin, std::size_t end) {
      for (std::size_t i = begin; i < end; ++i)
        for (int c = 0; c < 3; ++c)
          p (i, c) = inverse[i] * r (i, c) +
                     (linked[i] ? static_cast<Scalar> (zc (i / kAggregate, c)) : Scalar (0)) +
                     beta[c] * p (i, c);
    });
  };
  Residual sums = detail::parallelSum<Residual> (
      n, threads,
      [&] (std::size_t begin, std::size_t end) {
        Residual partial;
        for (std::size_t i = begin; i < end; ++i)
          sumRow (i, partial);
        return partial;
      },
      kRowsPerTask);
  coarseCorrection (sums.rz);
  p.setZero ();
  const Scalar no_beta[3] = {0, 0, 0};
  updateDirection (no_beta);
  detail::Sum3 rz = sums.rz;
  double residual = std::sqrt (sums.rr);
  int it = 0;
  while (residual > target && it < max_iterations)
  {
    const detail::Sum3 pq = applyA ();
    Scalar alpha[3];
    for (int c = 0; c < 3; ++c)
      alpha[c] = static_cast<Scalar> (pq.v[c] > 0.0 ? rz.v[c] / pq.v[c] : 0.0);
    // The step and the new residual's sums in one pass.
    sums = detail::parallelSum<Residual> (
        n, threads,
        [&] (std::size_t begin, std::size_t end) {
          Residual partial;
          for (std::size_t i = begin; i < end; ++i)
          {
            for (int c = 0; c < 3; ++c)
            {
              d (i, c) += alpha[c] * p (i, c);
              r (i, c) -= alpha[c] * q (i, c);
            }
            sumRow (i, partial);
          }
          return partial;
        },
        kRowsPerTask);
    residual = std::sqrt (sums.rr);
    ++it;
    if (params.progress && (done + it) % 10 == 0)
      params.progress (done + it, scale > 0.0 ? residual / scale : 0.0);
    if (residual <= target)
      break;
    coarseCorrection (sums.rz);
    Scalar beta[3];
    for (int c = 0; c < 3; ++c)
      beta[c] = static_cast<Scalar> (rz.v[c] > 0.0 ? sums.rz.v[c] / rz.v[c] : 0.0);
    rz = sums.rz;
    updateDirection (beta);
  }
  // Single precision overflows where the residual passes about 3e38 (a cloud near that
  // size): its correction is then dropped and the phase in double starts from x itself.
  if (d.allFinite ())
    x += d.template cast<double> ();
  return it;
}

} // namespace

struct TikhonovSystem::Impl
{
  Impl (const PointGraph &g, double strength, const TikhonovParams &p)
  : graph (g), gamma (strength), params (p)
  {
  }

  const PointGraph &graph;
  const double gamma;
  const TikhonovParams params;
  std::vector<double> degree;                          ///< conjugate gradient
  std::unique_ptr<AggregationPreconditioner> coarse;   ///< conjugate gradient
  std::vector<VertexIndex> components;                 ///< residualComponents
  std::unique_ptr<detail::CholmodFactor> cholmod;      ///< CHOLMOD

  /** Nothing set up: gamma 0 or a graph without entries, the identity. */
  bool
  identity () const { return !coarse && !cholmod; }

  /** The conjugate gradient in mixed precision: a correction of x = f solved with its
   *  vectors in single precision, the residual of the result recomputed in double, and,
   *  where it is still above the tolerance, a further correction in double precision. */
  Signal3
  conjugateGradient (const Signal3 &f, SolverReport &report) const
  {
    const int threads = params.num_threads;
    const double g2 = 2.0 * gamma;
    const double scale = detail::residualScale (components, f, threads);
    const double target = params.tolerance * scale;
    Signal3 x = detail::matrixOnHugePages<Signal3> (f.rows ()), r;
    x = f;
    double residual = trueResidual (graph, f, x, g2, threads, r);
    int it = 0;
    if (residual > target && params.max_iterations > 0)
    {
      it += correct<float> (graph, g2, degree, *coarse, r,
                            std::max (target, kSinglePrecisionReach * residual),
                            params.max_iterations, it, params, scale, x);
      residual = trueResidual (graph, f, x, g2, threads, r);
      if (residual > target && it < params.max_iterations)
      {
        it += correct<double> (graph, g2, degree, *coarse, r, target, params.max_iterations - it,
                               it, params, scale, x);
        residual = trueResidual (graph, f, x, g2, threads, r);
      }
    }
    report.iterations = it;
    report.residual = scale > 0.0 ? residual / scale : 0.0;
    report.converged = residual <= target;
    return x;
  }
};

TikhonovSystem::TikhonovSystem (const PointGraph &graph, double gamma,
                                const TikhonovParams &params)
{
  detail::requireSolverSettings (gamma, params.num_threads, params.tolerance,
                                 params.max_iterations);
  impl_ = std::make_unique<Impl> (graph, gamma, params);
  if (gamma == 0.0 || graph.numEntries () == 0)
    return;  // the identity
  impl_->components = detail::residualComponents (graph, params.num_threads);
  if (params.solver == TikhonovSolver::CHOLMOD)
    impl_->cholmod = std::make_unique<detail::CholmodFactor> (graph, gamma);
  else
  {
    impl_->degree = weightedDegree (graph, params.num_threads);
    impl_->coarse = std::make_unique<AggregationPreconditioner> (graph, impl_->degree, 2.0 * gamma,
                                                                 params.num_threads);
  }
}

TikhonovSystem::~TikhonovSystem () = default;
TikhonovSystem::TikhonovSystem (TikhonovSystem &&) noexcept = default;
TikhonovSystem &TikhonovSystem::operator= (TikhonovSystem &&) noexcept = default;

Signal3
TikhonovSystem::solve (const Signal3 &f, SolverReport *report) const
{
  if (!impl_)
    throw std::logic_error ("TikhonovSystem::solve on a system moved from");
  const Impl &s = *impl_;
  detail::requireSolverSignal (s.graph, f);
  SolverReport local;
  SolverReport &out = report ? *report : local;
  out = SolverReport{};
  if (s.identity ())
  {
    out.converged = true;
    return f;
  }
  if (s.cholmod)
  {
    Signal3 x = s.cholmod->solve (f);
    detail::requireSaneResult (x, f, s.gamma, "Tikhonov (CHOLMOD)");
    out.converged = true;
    out.iterations = 1;
    Signal3 r;
    const double residual = trueResidual (s.graph, f, x, 2.0 * s.gamma, s.params.num_threads, r);
    const double scale = detail::residualScale (s.components, f, s.params.num_threads);
    out.residual = scale > 0.0 ? residual / scale : 0.0;
    return x;
  }
  Signal3 x = s.conjugateGradient (f, out);
  detail::requireSaneResult (x, f, s.gamma, "Tikhonov");
  return x;
}

Signal3
solveTikhonov (const PointGraph &graph, const Signal3 &f, double gamma,
               const TikhonovParams &params, SolverReport *report)
{
  detail::requireSolverSignal (graph, f);  // before the set-up: a bad signal fails at once
  return TikhonovSystem (graph, gamma, params).solve (f, report);
}

} // namespace core
} // namespace pcl_graph_denoise

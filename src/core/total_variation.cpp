/*
 * pcl_graph_denoise: graph-signal-processing point cloud denoising for PCL.
 * SPDX-License-Identifier: BSD-3-Clause
 */
#include <pcl_graph_denoise/core/operators.h>
#include <pcl_graph_denoise/core/solvers.h>

#include "huge_pages.h"
#include "parallel.h"
#include "solver_support.h"
#include "wide_kernels.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <stdexcept>
#include <type_traits>

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

/** x-bar of the solver, in single precision (see TotalVariationSystem::Impl::solve). */
using FloatSignal = Eigen::Matrix<float, Eigen::Dynamic, 3, Eigen::RowMajor>;

/** The entries of a vertex range are updated a batch of consecutive entries at a time
 *  (across row ends): their differences gathered first, then the dual step, the projection
 *  and the weighting by sqrt(w) over the batch as over plain arrays (vectorised: the file
 *  is compiled without errno and trap semantics for it), then each row's adjoint summed
 *  in entry order. */
constexpr std::size_t kDualBatch = 64;

/** The differences x_i - x_j of the `count` entries from `first` on (x row-major n x 3),
 *  into d, as T; `row` and `row_end` follow the row of the entry (start them at the
 *  range's first row and its end). */
template <typename Source, typename T>
PCL_GRAPH_DENOISE_KERNEL inline void
gatherDifferences (const std::uint64_t *row_ptr, const VertexIndex *col, const Source *x,
                   std::uint64_t first, std::size_t count, std::size_t &row,
                   std::uint64_t &row_end, T (&d)[3][kDualBatch])
{
  const Source *xi = x + 3 * row;
  for (std::size_t t = 0; t < count; ++t)
  {
    while (first + t >= row_end)
    {
      row_end = row_ptr[++row + 1];
      xi = x + 3 * row;
    }
    const Source *xj = x + 3 * std::size_t (col[first + t]);
    d[0][t] = static_cast<T> (xi[0] - xj[0]);
    d[1][t] = static_cast<T> (xi[1] - xj[1]);
    d[2][t] = static_cast<T> (xi[2] - xj[2]);
  }
}

/** `sum` plus, in entry order, the `count` entries' norms of sqrt(w) d (d = x_i - x_j,
 *  `weight` the entries' w): their part of 2 TV(x). */
PCL_GRAPH_DENOISE_KERNEL inline double
batchVariation (const double (&d)[3][kDualBatch], const float *weight, std::size_t count,
                TotalVariationNorm norm, double sum)
{
  double length[kDualBatch];
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
      length[t] = std::abs (s * d[0][t]) + std::abs (s * d[1][t]) + std::abs (s * d[2][t]);
    }
  for (std::size_t t = 0; t < count; ++t)
    sum += length[t];
  return sum;
}

/** What one dual pass reads and writes, as plain arrays (row-major n x 3 for the
 *  vertex signals, one array per coordinate for the duals); x-bar in single or double
 *  precision (Bar). */
template <typename Bar>
struct DualPass
{
  const std::uint64_t *row_ptr;
  const VertexIndex *col;
  const float *root_weight;
  const Bar *xbar;
  float *y[3];
  double *gty;
  float step, gamma;
  TotalVariationNorm norm;
  /** When not null, the pass also sums the entries' part of TV(x) (a gap check's, the
   *  iteration before: x is still that iterate), with the graph's weights. */
  const double *x;
  const float *weight;
};

/** The dual pass over the rows [begin, end): y <- proj(y + step grad xbar) onto the dual
 *  ball of radius gamma of the norm (odd in y and the difference, so antisymmetry holds
 *  exactly), then gty = grad^T y. The isotropic shrink factor is computed for every entry
 *  and applied where the ball is left, without a branch; an entry inside keeps its value
 *  (times 1). The duals and the entries' terms sqrt(w) y are single precision (the edge
 *  differences are small numbers of similar size); a row's sum is accumulated in double,
 *  in entry order. With p.x, returns the sum of the entries' norms of sqrt(w) (x_i - x_j)
 *  over [begin, end) as totalVariation sums a block (2 TV(x) over the blocks); else 0. A
 *  kernel (wide_kernels.h): each iteration runs it through detail::wide. */
template <typename Bar>
PCL_GRAPH_DENOISE_KERNEL inline double
dualPass (const DualPass<Bar> &p, std::size_t begin, std::size_t end)
{
  float d[3][kDualBatch];
  double dx[3][kDualBatch];
  double variation = 0.0;
  const std::uint64_t last = p.row_ptr[end];
  // The gather's row and the sums' row (with their ends).
  std::size_t row = begin, sum_row = begin;
  std::uint64_t row_end = p.row_ptr[begin + 1], sum_end = row_end;
  double acc0 = 0.0, acc1 = 0.0, acc2 = 0.0;
  for (std::uint64_t first = p.row_ptr[begin]; first < last; first += kDualBatch)
  {
    const std::size_t count =
        static_cast<std::size_t> (std::min<std::uint64_t> (kDualBatch, last - first));
    if (p.x)
    {
      // The same entries as x-bar's gather below, from the same row.
      std::size_t x_row = row;
      std::uint64_t x_row_end = row_end;
      gatherDifferences (p.row_ptr, p.col, p.x, first, count, x_row, x_row_end, dx);
      variation = batchVariation (dx, p.weight + first, count, p.norm, variation);
    }
    gatherDifferences (p.row_ptr, p.col, p.xbar, first, count, row, row_end, d);
    float *__restrict y0 = p.y[0] + first;
    float *__restrict y1 = p.y[1] + first;
    float *__restrict y2 = p.y[2] + first;
    const float *__restrict w = p.root_weight + first;
    float *__restrict d0 = d[0];
    float *__restrict d1 = d[1];
    float *__restrict d2 = d[2];
    const float step = p.step, gamma = p.gamma;
    if (p.norm == TotalVariationNorm::ISOTROPIC)
    {
      const float gamma2 = gamma * gamma;
      for (std::size_t t = 0; t < count; ++t)
      {
        const float v0 = y0[t] + step * d0[t];
        const float v1 = y1[t] + step * d1[t];
        const float v2 = y2[t] + step * d2[t];
        const float squared = v0 * v0 + v1 * v1 + v2 * v2;
        const float shrink = gamma / std::sqrt (squared);
        const float scale = squared > gamma2 ? shrink : 1.0f;
        y0[t] = v0 * scale;
        y1[t] = v1 * scale;
        y2[t] = v2 * scale;
        d0[t] = w[t] * y0[t];
        d1[t] = w[t] * y1[t];
        d2[t] = w[t] * y2[t];
      }
    }
    else
    {
      for (std::size_t t = 0; t < count; ++t)
      {
        y0[t] = std::max (-gamma, std::min (gamma, y0[t] + step * d0[t]));
        y1[t] = std::max (-gamma, std::min (gamma, y1[t] + step * d1[t]));
        y2[t] = std::max (-gamma, std::min (gamma, y2[t] + step * d2[t]));
        d0[t] = w[t] * y0[t];
        d1[t] = w[t] * y1[t];
        d2[t] = w[t] * y2[t];
      }
    }
    for (std::size_t t = 0; t < count; ++t)
    {
      while (first + t >= sum_end)
      {
        double *g = p.gty + 3 * sum_row;
        g[0] = acc0;
        g[1] = acc1;
        g[2] = acc2;
        acc0 = acc1 = acc2 = 0.0;
        sum_end = p.row_ptr[++sum_row + 1];
      }
      acc0 += double (d0[t]);
      acc1 += double (d1[t]);
      acc2 += double (d2[t]);
    }
  }
  // The last row with entries, and the rows without any after it.
  for (; sum_row < end; ++sum_row)
  {
    double *g = p.gty + 3 * sum_row;
    g[0] = acc0;
    g[1] = acc1;
    g[2] = acc2;
    acc0 = acc1 = acc2 = 0.0;
  }
  return variation;
}

/** TV(x) = 1/2 sum over stored entries of the norm of sqrt(w) (x_i - x_j). A block's
 *  entries are taken a batch at a time, their differences gathered first and their norms
 *  computed over the batch (vectorised), then summed in entry order. */
double
totalVariation (const PointGraph &graph, const Signal3 &x, TotalVariationNorm norm,
                int num_threads)
{
  const double *points = x.data ();
  const auto kernel = [&] (std::size_t begin, std::size_t end) PCL_GRAPH_DENOISE_KERNEL {
    double sum = 0.0;
    double d[3][kDualBatch];
    std::size_t i = begin;
    std::uint64_t row_end = graph.row_ptr[begin + 1];
    const std::uint64_t last = graph.row_ptr[end];
    for (std::uint64_t first = graph.row_ptr[begin]; first < last; first += kDualBatch)
    {
      const std::size_t count =
          static_cast<std::size_t> (std::min<std::uint64_t> (kDualBatch, last - first));
      gatherDifferences (graph.row_ptr.data (), graph.col.data (), points, first, count, i,
                         row_end, d);
      sum = batchVariation (d, graph.weight.data () + first, count, norm, sum);
    }
    return sum;
  };
  return 0.5 * detail::parallelSum<double> (
                   graph.numVertices (), num_threads,
                   [&] (std::size_t begin, std::size_t end) { return detail::wide (kernel, begin, end); });
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

struct TotalVariationSystem::Impl
{
  Impl (const PointGraph &g, double strength, const TotalVariationParams &p)
  : graph (g), gamma (strength), params (p)
  {
  }

  const PointGraph &graph;
  const double gamma;
  const TotalVariationParams params;
  /** Diagonal preconditioning (Pock and Chambolle 2011, alpha = 1): each vertex's primal
   *  step is the inverse of its row sum of |grad|, tau_i = 1 / sum_j sqrt(w_ij), and each
   *  entry's dual step sigma_e = 1 / (2 sqrt(w_e)), so that sigma_e sqrt(w_e) = 1/2 and
   *  the dual update needs no weight. Empty: nothing set up (gamma 0, or no vertex with a
   *  weighted edge), the identity. */
  std::vector<float> root_weight;
  std::vector<double> tau;
  /** The graph's components (detail::residualComponents: empty for one): x-bar is stored
   *  about each component's root. */
  std::vector<VertexIndex> component_root;
  /** The smallest positive tau: the data term's modulus of strong convexity in the
   *  preconditioned metric, for the acceleration. */
  double min_tau = 0.0;
  /** The sum of sqrt(w) over the entries, for the mean length of the entries' differences. */
  double root_weight_sum = 0.0;
  /** The working arrays, kept from one solve to the next (each solve sets those it uses
   *  before it reads them): the duals, grad^T y, and x-bar in single or double precision
   *  (see solve). */
  mutable Duals y;
  mutable Signal3 gty;
  mutable FloatSignal xbar_single;
  mutable Signal3 xbar_double;

  bool
  identity () const { return root_weight.empty (); }

  Signal3
  solve (const Signal3 &f, SolverReport &out) const;
};

TotalVariationSystem::TotalVariationSystem (const PointGraph &graph, double gamma,
                                            const TotalVariationParams &params)
{
  detail::requireSolverSettings (gamma, params.num_threads, params.tolerance,
                                 params.max_iterations);
  const bool identity = gamma == 0.0 || graph.numEntries () == 0;
  // The duals are single precision and bounded by gamma (unless nothing is solved).
  if (!identity && !(gamma <= double (std::numeric_limits<float>::max ())))
  {
    char text[160];
    std::snprintf (text, sizeof (text),
                   "gamma = %g is too large for the total-variation solver, whose duals are "
                   "single precision: must be at most %g",
                   gamma, double (std::numeric_limits<float>::max ()));
    throw std::invalid_argument (text);
  }
  impl_ = std::make_unique<Impl> (graph, gamma, params);
  if (identity)
    return;
  const int threads = params.num_threads;
  std::vector<double> tau = detail::rootDegree (graph, threads);
  double min_tau = std::numeric_limits<double>::infinity ();
  double root_weight_sum = 0.0;
  for (double &t : tau)
  {
    root_weight_sum += t;
    t = t > 0.0 ? 1.0 / t : 0.0;
    if (t > 0.0)
      min_tau = std::min (min_tau, t);
  }
  if (!std::isfinite (min_tau))  // no vertex with a weighted edge: the identity
    return;
  Impl &s = *impl_;
  s.root_weight_sum = root_weight_sum;
  s.tau = std::move (tau);
  s.min_tau = min_tau;
  s.component_root = detail::residualComponents (graph, threads);
  detail::resizeOnHugePages (s.root_weight, graph.numEntries ());
  detail::parallelFor (s.root_weight.size (), threads, [&] (std::size_t begin, std::size_t end) {
    for (std::size_t e = begin; e < end; ++e)
      s.root_weight[e] = std::sqrt (graph.weight[e]);
  });
}

TotalVariationSystem::~TotalVariationSystem () = default;
TotalVariationSystem::TotalVariationSystem (TotalVariationSystem &&) noexcept = default;
TotalVariationSystem &TotalVariationSystem::operator= (TotalVariationSystem &&) noexcept = default;

Signal3
TotalVariationSystem::solve (const Signal3 &f, SolverReport *report) const
{
  if (!impl_)
    throw std::logic_error ("TotalVariationSystem::solve on a system moved from");
  detail::requireSolverSignal (impl_->graph, f);
  SolverReport local;
  SolverReport &out = report ? *report : local;
  out = SolverReport{};
  if (impl_->identity ())
  {
    out.converged = true;
    return f;
  }
  return impl_->solve (f, out);
}

Signal3
solveTotalVariation (const PointGraph &graph, const Signal3 &f, double gamma,
                     const TotalVariationParams &params, SolverReport *report)
{
  detail::requireSolverSignal (graph, f);  // before the set-up: a bad signal fails at once
  return TotalVariationSystem (graph, gamma, params).solve (f, report);
}

Signal3
TotalVariationSystem::Impl::solve (const Signal3 &f, SolverReport &out) const
{
  const std::size_t n = graph.numVertices ();
  const int threads = params.num_threads;
  // A global `scale` multiplies the primal steps and divides the dual ones, shrunk as in
  // Chambolle and Pock's accelerated algorithm 2 with the data term's modulus of strong
  // convexity in the preconditioned metric, the smallest tau (with the mean tau instead,
  // the fountain scan's weakly linked pieces diverged). On noisy spheres this halves the
  // iterations at strong smoothing.
  const float bound_gamma = static_cast<float> (gamma);
  double scale = 1.0;

  // Warm start: every edge difference of a point cloud is non-zero, so nearly every
  // dual ends on the boundary of its ball, along the edge's difference. Starting the
  // duals there for the differences of f (feasible, and odd in (i, j) as required)
  // and the primal at f - grad^T y cuts the iterations several times.
  const auto rows = static_cast<Eigen::Index> (n);
  Signal3 x = detail::matrixOnHugePages<Signal3> (rows);
  // x-bar only feeds the dual step's differences: single precision (the gather of the
  // neighbours' x-bar is the dual pass's stall; half the bytes, about 10% less time per
  // iteration at a million points), each vertex's about f at its component's root (its
  // smallest vertex, first on the Morton curve), so that a cloud far from the origin, or
  // one point far from the rest, keeps its differences: each is rounded to about 2^-24
  // times the component's extent (within twice the resolution of a float coordinate at
  // the component's far end; at a thousand spacings across, 6e-5 of a spacing), which
  // only perturbs the dual steps. Every entry with a weight joins two vertices of one
  // component (the graph is symmetric), so its difference keeps x-bar's origin out and
  // stays exactly odd in (i, j). The iterate x, the objective and the gap stay in double.
  const VertexIndex *roots = component_root.empty () ? nullptr : component_root.data ();
  const auto originOf = [&] (std::size_t i) {
    return f.data () + 3 * std::size_t (roots ? roots[i] : 0);
  };
  if (gty.rows () == 0)  // the first solve; both, or neither should one fail
  {
    Duals new_y = detail::matrixOnHugePages<Duals> (static_cast<Eigen::Index> (graph.numEntries ()));
    Signal3 new_gty = detail::matrixOnHugePages<Signal3> (rows);
    y.swap (new_y);
    gty.swap (new_gty);
  }
  // f's total variation comes with the warm start (the cold start's objective), summed
  // over the same entries.
  const auto warm_kernel = [&] (std::size_t begin, std::size_t end) PCL_GRAPH_DENOISE_KERNEL {
    double variation = 0.0;
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
        variation += double (root_weight[e]) *
                     (params.norm == TotalVariationNorm::ISOTROPIC
                          ? length
                          : std::abs (d[0]) + std::abs (d[1]) + std::abs (d[2]));
      }
      for (int c = 0; c < 3; ++c)
        x (i, c) = f (i, c) - acc[c];
    }
    return variation;
  };
  // Sets the warm start; returns TV(f).
  const auto warmStart = [&] () {
    return 0.5 * detail::parallelSum<double> (n, threads, [&] (std::size_t begin, std::size_t end) {
             return detail::wide (warm_kernel, begin, end);
           });
  };
  const double f_variation = warmStart ();
  // With a gamma large against the cloud's differences the minimiser is nearly constant
  // and that start lies far from it (about gamma times the degree): then the cold start,
  // duals 0 and x = f, when the warm start's objective is more than kColdStart times
  // f's. (At the filters' derived gammas the ratio is 1-7 on noisy spheres and cubes,
  // where the warm start still converges faster and lands closer to the surface.)
  constexpr double kColdStart = 100.0;
  const double warm_objective =
      0.5 * (x - f).squaredNorm () + gamma * totalVariation (graph, x, params.norm, threads);
  const double cold_objective = gamma * f_variation;
  const bool warm = warm_objective <= kColdStart * cold_objective;
  if (!warm)
  {
    y.setZero ();
    x = f;
  }
  // Single precision unless the tolerance asks for more than its rounding of the
  // differences allows: 2^-24 R / L relative, R the farthest coordinate from its origin, L
  // the entries' mean length (weighted by sqrt(w)). On a noisy sphere of 20,000 points
  // (R / L about 54: 3.2e-6) the gap stalls near that rounding, 3e-6, where double reaches
  // 1e-8; a tolerance of at least kSinglePrecisionMargin times it is met as fast in either
  // (on the 1M sphere the rounding is 1.3e-5, against the filters' 2e-2).
  constexpr double kSinglePrecisionMargin = 10.0;
  struct Farthest
  {
    double value = 0.0;
    Farthest &
    operator+= (const Farthest &o)
    {
      value = std::max (value, o.value);
      return *this;
    }
  };
  const double reach =
      detail::parallelSum<Farthest> (n, threads, [&] (std::size_t begin, std::size_t end) {
        Farthest r;
        for (std::size_t i = begin; i < end; ++i)
          for (int c = 0; c < 3; ++c)
            r.value = std::max (r.value, std::abs (f (i, c) - originOf (i)[c]));
        return r;
      }).value;
  const double mean_length = 2.0 * f_variation / root_weight_sum;
  const bool single = mean_length > 0.0 &&
                      params.tolerance >= kSinglePrecisionMargin * 0x1p-24 * reach / mean_length;
  if (single && xbar_single.rows () == 0)
    xbar_single = detail::matrixOnHugePages<FloatSignal> (rows);
  if (!single && xbar_double.rows () == 0)
    xbar_double = detail::matrixOnHugePages<Signal3> (rows);
  // Runs `body` on the solve's x-bar (a float or a double pointer, row-major n x 3).
  const auto withXbar = [&] (const auto &body) {
    return single ? body (xbar_single.data ()) : body (xbar_double.data ());
  };
  withXbar ([&] (auto *bar) {
    using Bar = std::decay_t<decltype (*bar)>;
    detail::parallelFor (n, threads, [&] (std::size_t begin, std::size_t end) {
      for (std::size_t i = begin; i < end; ++i)
        for (int c = 0; c < 3; ++c)
          bar[3 * i + c] = static_cast<Bar> (x (i, c) - originOf (i)[c]);
    });
  });
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
  double last_objective = start_objective;  // the primal objective at the last check
  // |x - f|^2, <f, grad^T y> and |grad^T y|^2 of a check, and TV(x) to come.
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
  Terms terms;
  bool pending = false;  // a check whose TV(x) the next dual pass sums
  // The duality gap of the check at iteration `it`: P(x) - D(y), with
  // D(y) = <f, grad^T y> - 1/2 |grad^T y|^2 (y is feasible after the projection). True
  // when it meets the tolerance; else schedules the next check.
  const auto gapMet = [&] (double variation) {
    const double primal = 0.5 * terms.data + gamma * variation;
    last_objective = primal;
    const double gap = primal - (terms.cross - 0.5 * terms.adjoint);
    // The floor: with a gamma so small that the objective is below the rounding of x
    // in double, the gap measures only that rounding and never meets the tolerance.
    // Stopping there leaves x within sqrt(2 tolerance) 1e-10 |f| of the minimiser
    // (the objective is 1-strongly convex): nothing a float output can show.
    const double objective_scale = std::max (primal, 1e-20 * f_norm2);
    out.residual = gap / objective_scale;
    if (params.progress)
      params.progress (it, out.residual);
    if (gap <= params.tolerance * objective_scale)
      return true;
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
    return false;
  };
  while (it < params.max_iterations)
  {
    // Dual ascent with projection, then the adjoint of each row (dualPass); after a
    // check, with TV(x) of its iterate, which x still holds.
    const double variation = withXbar ([&] (const auto *bar) {
      const DualPass<std::decay_t<decltype (*bar)>> pass{
          graph.row_ptr.data (),
          graph.col.data (),
          root_weight.data (),
          bar,
          {y.col (0).data (), y.col (1).data (), y.col (2).data ()},
          gty.data (),
          static_cast<float> (0.5 / scale),
          bound_gamma,
          params.norm,
          pending ? x.data () : nullptr,
          graph.weight.data ()};
      const auto dual = [&] (std::size_t begin, std::size_t end) PCL_GRAPH_DENOISE_KERNEL {
        return dualPass (pass, begin, end);
      };
      return 0.5 * detail::parallelSum<double> (n, threads, [&] (std::size_t begin, std::size_t end) {
               return detail::wide (dual, begin, end);
             });
    });
    if (pending)
    {
      pending = false;
      if (gapMet (variation))
      {
        out.converged = true;
        break;  // with x the check's iterate (the duals moved on: they are not returned)
      }
    }
    // Primal step: prox of 1/2 |x - f|^2, then the accelerated extrapolation.
    const double theta = 1.0 / std::sqrt (1.0 + 2.0 * scale * min_tau);
    // (Into x-bar of either precision: Bar.)
    const auto primal_step = [&, scale] (auto *__restrict xbars, std::size_t begin,
                                         std::size_t end) PCL_GRAPH_DENOISE_KERNEL {
      using Bar = std::decay_t<decltype (*xbars)>;
      double *__restrict xs = x.data ();
      const double *__restrict fs = f.data ();
      const double *__restrict gtys = gty.data ();
      const double *__restrict taus = tau.data ();
      for (std::size_t i = begin; i < end; ++i)
      {
        const double step_i = scale * taus[i];
        const double *o = originOf (i);
        for (std::size_t c = 3 * i; c < 3 * i + 3; ++c)
        {
          const double previous = xs[c];
          const double next = (previous - step_i * gtys[c] + step_i * fs[c]) / (1.0 + step_i);
          xs[c] = next;
          xbars[c] = static_cast<Bar> (next + theta * (next - previous) - o[c - 3 * i]);
        }
      }
    };
    withXbar ([&] (auto *bar) {
      const auto primal = [&] (std::size_t begin, std::size_t end) PCL_GRAPH_DENOISE_KERNEL {
        primal_step (bar, begin, end);
      };
      detail::parallelFor (n, threads, [&] (std::size_t begin, std::size_t end) {
        detail::wide (primal, begin, end);
      });
    });
    scale *= theta;
    ++it;

    // A gap check: the vertex terms now, while grad^T y is this iteration's; TV(x) with
    // the next dual pass (one pass over the graph fewer), or at once at the cap.
    if (it == next_check || it == params.max_iterations)
    {
      terms = detail::parallelSum<Terms> (n, threads, [&] (std::size_t begin, std::size_t end) {
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
      if (it < params.max_iterations)
        pending = true;
      else if (gapMet (totalVariation (graph, x, params.norm, threads)))
        out.converged = true;
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

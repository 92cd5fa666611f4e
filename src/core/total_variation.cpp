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
 * The dual variable lives on the undirected edges, each once: the entries (i, j) of row i
 * with j > i, copied into a CSR of their own (TotalVariationSystem::Impl::edge_ptr). The
 * dual update y_e <- proj(y_e + s sqrt(w_e) (xbar_i - xbar_j)) runs once per edge (it ran
 * on both entries of each edge, kept antisymmetric), and its adjoint
 *   (grad^T y)_i = sum_{e = (i, j), j > i} sqrt(w_e) y_e - sum_{e = (j, i), j < i} sqrt(w_e) y_e
 * is summed as the edges are updated, in fixed blocks of kDualBlock vertices: a row's own
 * edges into its sum, and the edge's other end, when in the same block, into that row's
 * sum to come (it follows in the block), else into the edge's slot of terms between
 * blocks; the primal step adds to each vertex the slots that reach it from an earlier
 * block (cross_ptr, cross_slot), after the pass. Every sum is taken in an order fixed by the graph and the blocks alone, so the
 * result does not depend on the number of threads. Half the duals' memory and traffic and
 * half the updates: on a million points an iteration takes 0.86 of the time it took.
 */

namespace {

/** The duals, one per edge, one array per coordinate (column-major), so that the update
 *  of consecutive edges runs over consecutive floats. */
using Duals = Eigen::Matrix<float, Eigen::Dynamic, 3, Eigen::ColMajor>;

/** x-bar of the solver, in single precision (see TotalVariationSystem::Impl::solve). */
using FloatSignal = Eigen::Matrix<float, Eigen::Dynamic, 3, Eigen::RowMajor>;

/** The edges of a block are updated a batch of consecutive edges at a time (across row
 *  ends): their differences gathered first, then the dual step, the projection and the
 *  weighting by sqrt(w) over the batch as over plain arrays (vectorised: the file is
 *  compiled without errno and trap semantics for it), then the adjoint summed in edge
 *  order. */
constexpr std::size_t kDualBatch = 64;

/** The dual pass's blocks of vertices (parallelSum's blocks, fixed whatever the threads):
 *  an edge whose ends lie in one block is summed within it, the others by the primal step
 *  (at a million Morton-ordered points, 7% of the edges). */
constexpr std::size_t kDualBlock = 4096;

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

/** `sum` plus, in entry order, the `count` entries' norms of sqrt(w) d (d = x_i - x_j):
 *  their part of 2 TV(x) over a graph's entries, or of TV(x) over the edges. `weight` is
 *  w (kRoot false: sqrt(w) is taken in double) or sqrt(w) itself (kRoot true: the TV
 *  solver's single-precision roots). */
template <bool kRoot>
PCL_GRAPH_DENOISE_KERNEL inline double
batchVariation (const double (&d)[3][kDualBatch], const float *weight, std::size_t count,
                TotalVariationNorm norm, double sum)
{
  double length[kDualBatch];
  const auto root = [&] (std::size_t t) {
    return kRoot ? double (weight[t]) : std::sqrt (double (weight[t]));
  };
  if (norm == TotalVariationNorm::ISOTROPIC)
    for (std::size_t t = 0; t < count; ++t)
    {
      const double s = root (t);
      const double d0 = s * d[0][t], d1 = s * d[1][t], d2 = s * d[2][t];
      length[t] = std::sqrt (d0 * d0 + d1 * d1 + d2 * d2);
    }
  else
    for (std::size_t t = 0; t < count; ++t)
    {
      const double s = root (t);
      length[t] = std::abs (s * d[0][t]) + std::abs (s * d[1][t]) + std::abs (s * d[2][t]);
    }
  for (std::size_t t = 0; t < count; ++t)
    sum += length[t];
  return sum;
}

/** The edges of the TV solver (each undirected edge once, as a CSR over the rows of its
 *  smaller end) with their sqrt(w), and for every vertex the edges that reach it from an
 *  earlier block of kDualBlock vertices. */
struct EdgeArrays
{
  const std::uint64_t *ptr;
  const VertexIndex *col;
  const float *root_weight;
  /** Per block, the first slot of its edges to later blocks in `cross` (their terms, in
   *  edge order); per vertex, the slots of the edges that reach it (cross_ptr). */
  const std::uint64_t *block_cross;
  const std::uint64_t *cross_ptr;
  const std::uint64_t *cross_slot;
  /** The terms sqrt(w) y of the edges between blocks, 3 per slot (written by the pass). */
  float *cross;
};

/** Sums grad^T y over the rows of one block [begin, end) as its edges' terms
 *  t_e = sqrt(w_e) y_e come, in edge order: row i's own edges into row i's sum, the other
 *  end j (> i) into j's, kept in `lower` while j lies in the block, else stored in the
 *  edge's cross slot (consecutive, from the block's first). A row's sum is written to gty
 *  when its edges end; what edges from earlier blocks add comes later (crossAdjoint). */
class BlockAdjoint
{
public:
  BlockAdjoint (const EdgeArrays &edges, double *gty, std::size_t begin, std::size_t end)
  : ptr_ (edges.ptr), col_ (edges.col), gty_ (gty), begin_ (begin), end_ (end), row_ (begin),
    row_end_ (edges.ptr[begin + 1]),
    cross_ (edges.cross ? edges.cross + 3 * edges.block_cross[begin / kDualBlock] : nullptr),
    lower_ (scratch ())
  {
    lower_.assign (3 * (end - begin), 0.0);
  }

  /** The term of edge `e` (the next in order). */
  PCL_GRAPH_DENOISE_KERNEL inline void
  add (std::uint64_t e, float t0, float t1, float t2)
  {
    while (e >= row_end_)
      nextRow ();
    acc_[0] += double (t0);
    acc_[1] += double (t1);
    acc_[2] += double (t2);
    const std::size_t j = col_[e];
    if (j < end_)
    {
      double *l = lower_.data () + 3 * (j - begin_);
      l[0] -= double (t0);
      l[1] -= double (t1);
      l[2] -= double (t2);
    }
    else
    {
      cross_[0] = t0;
      cross_[1] = t1;
      cross_[2] = t2;
      cross_ += 3;
    }
  }

  /** Writes the rows left (the last with edges and those without after it). */
  PCL_GRAPH_DENOISE_KERNEL inline void
  finish ()
  {
    while (row_ < end_)
      nextRow ();
  }

private:
  /** The calling thread's sums to come, kept from block to block (and iteration to
   *  iteration on a thread that stays): no allocation per block of a solver's pass. */
  static std::vector<double> &
  scratch ()
  {
    thread_local std::vector<double> lower;
    return lower;
  }

  PCL_GRAPH_DENOISE_KERNEL inline void
  nextRow ()
  {
    const double *l = lower_.data () + 3 * (row_ - begin_);
    double *g = gty_ + 3 * row_;
    for (int c = 0; c < 3; ++c)
      g[c] = l[c] + acc_[c];
    acc_[0] = acc_[1] = acc_[2] = 0.0;
    if (++row_ < end_)  // (past the block's last row there is no next end to read)
      row_end_ = ptr_[row_ + 1];
  }

  const std::uint64_t *ptr_;
  const VertexIndex *col_;
  double *gty_;
  std::size_t begin_, end_, row_;
  std::uint64_t row_end_;
  float *cross_;  ///< the next cross slot's terms
  double acc_[3] = {0.0, 0.0, 0.0};
  std::vector<double> &lower_;
};

/** Vertex i's part of grad^T y from the edges that reach it from earlier blocks:
 *  the sum of their terms sqrt(w_e) y_e (from their cross slots), in edge order, to
 *  subtract. */
PCL_GRAPH_DENOISE_KERNEL inline void
crossAdjoint (const EdgeArrays &edges, std::size_t i, double (&sum)[3])
{
  sum[0] = sum[1] = sum[2] = 0.0;
  for (std::uint64_t q = edges.cross_ptr[i]; q < edges.cross_ptr[i + 1]; ++q)
  {
    const float *t = edges.cross + 3 * edges.cross_slot[q];
    sum[0] += double (t[0]);
    sum[1] += double (t[1]);
    sum[2] += double (t[2]);
  }
}

/** What one dual pass reads and writes, as plain arrays (row-major n x 3 for the
 *  vertex signals, one array per coordinate for the duals); x-bar in single or double
 *  precision (Bar). */
template <typename Bar>
struct DualPass
{
  EdgeArrays edges;
  const Bar *xbar;
  float *y[3];
  double *gty;
  float step, gamma;
  TotalVariationNorm norm;
  /** When not null, the pass also sums the edges' part of TV(x) (a gap check's, the
   *  iteration before: x is still that iterate). */
  const double *x;
};

/** The dual pass over the edges of the block of rows [begin, end): y <- proj(y + step
 *  grad xbar) onto the dual ball of radius gamma of the norm, then grad^T y of the block's
 *  rows but for what reaches them from earlier blocks (BlockAdjoint; the primal step adds
 *  that). The isotropic shrink factor is computed for every edge and applied where the
 *  ball is left, without a branch; an edge inside keeps its value (times 1). The duals
 *  and the edges' terms sqrt(w) y are single precision (the edge differences are small
 *  numbers of similar size); a row's sum is accumulated in double, in edge order. With
 *  p.x, returns the sum of the edges' norms of sqrt(w) (x_i - x_j) over the block (TV(x)
 *  over the blocks); else 0. A kernel (wide_kernels.h): each iteration runs it through
 *  detail::wide. */
template <typename Bar>
PCL_GRAPH_DENOISE_KERNEL inline double
dualPass (const DualPass<Bar> &p, std::size_t begin, std::size_t end)
{
  float d[3][kDualBatch];
  double dx[3][kDualBatch];
  double variation = 0.0;
  const std::uint64_t *ptr = p.edges.ptr;
  const std::uint64_t last = ptr[end];
  std::size_t row = begin;  // the gather's row, with its end
  std::uint64_t row_end = ptr[begin + 1];
  BlockAdjoint adjoint (p.edges, p.gty, begin, end);
  for (std::uint64_t first = ptr[begin]; first < last; first += kDualBatch)
  {
    const std::size_t count =
        static_cast<std::size_t> (std::min<std::uint64_t> (kDualBatch, last - first));
    if (p.x)
    {
      // The same edges as x-bar's gather below, from the same row.
      std::size_t x_row = row;
      std::uint64_t x_row_end = row_end;
      gatherDifferences (ptr, p.edges.col, p.x, first, count, x_row, x_row_end, dx);
      variation = batchVariation<true> (dx, p.edges.root_weight + first, count, p.norm, variation);
    }
    gatherDifferences (ptr, p.edges.col, p.xbar, first, count, row, row_end, d);
    float *__restrict y0 = p.y[0] + first;
    float *__restrict y1 = p.y[1] + first;
    float *__restrict y2 = p.y[2] + first;
    const float *__restrict w = p.edges.root_weight + first;
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
      adjoint.add (first + t, d0[t], d1[t], d2[t]);
  }
  adjoint.finish ();
  return variation;
}

/** The sum over a CSR's entries (row_ptr over n rows, col, weight) of the norms of
 *  sqrt(w) (x_i - x_j), a block of rows at a time, each block's entries a batch at a time
 *  (their differences gathered first and their norms computed over the batch, vectorised),
 *  summed in entry order: weight is w (kRoot false) or sqrt(w) (kRoot true), as in
 *  batchVariation. */
template <bool kRoot>
double
csrVariation (const std::uint64_t *row_ptr, const VertexIndex *col, const float *weight,
              std::size_t n, const Signal3 &x, TotalVariationNorm norm, int num_threads)
{
  const double *points = x.data ();
  const auto kernel = [&] (std::size_t begin, std::size_t end) PCL_GRAPH_DENOISE_KERNEL {
    double sum = 0.0;
    double d[3][kDualBatch];
    std::size_t i = begin;
    std::uint64_t row_end = row_ptr[begin + 1];
    const std::uint64_t last = row_ptr[end];
    for (std::uint64_t first = row_ptr[begin]; first < last; first += kDualBatch)
    {
      const std::size_t count =
          static_cast<std::size_t> (std::min<std::uint64_t> (kDualBatch, last - first));
      gatherDifferences (row_ptr, col, points, first, count, i, row_end, d);
      sum = batchVariation<kRoot> (d, weight + first, count, norm, sum);
    }
    return sum;
  };
  return detail::parallelSum<double> (
      n, num_threads,
      [&] (std::size_t begin, std::size_t end) { return detail::wide (kernel, begin, end); },
      kDualBlock);
}

/** TV(x) over the solver's edges (each once), with their single-precision sqrt(w): the
 *  variation the dual pass sums with a check. */
double
edgeVariation (const EdgeArrays &edges, std::size_t n, const Signal3 &x, TotalVariationNorm norm,
               int num_threads)
{
  return csrVariation<true> (edges.ptr, edges.col, edges.root_weight, n, x, norm, num_threads);
}

/** TV(x) = 1/2 sum over the graph's stored entries (each edge twice) of the norm of
 *  sqrt(w) (x_i - x_j). */
double
totalVariation (const PointGraph &graph, const Signal3 &x, TotalVariationNorm norm,
                int num_threads)
{
  return 0.5 * csrVariation<false> (graph.row_ptr.data (), graph.col.data (), graph.weight.data (),
                                    graph.numVertices (), x, norm, num_threads);
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
  /** The undirected edges, each once (see the top of this file): row i's entries to
   *  j > i, in row order, as a CSR (edge_ptr, n + 1 offsets; edge_col) with their sqrt(w)
   *  in single precision; the edges between blocks of kDualBlock vertices numbered in
   *  edge order (their slots; block_cross: each block's first), and for each vertex the
   *  slots of those that reach it from an earlier block, in edge order (cross_ptr,
   *  cross_slot). Empty: nothing set up (gamma 0, or no vertex with a weighted edge), the
   *  identity. */
  std::vector<std::uint64_t> edge_ptr;
  std::vector<VertexIndex> edge_col;
  std::vector<float> root_weight;
  std::vector<std::uint64_t> block_cross;
  std::vector<std::uint64_t> cross_ptr;
  std::vector<std::uint64_t> cross_slot;
  /** Diagonal preconditioning (Pock and Chambolle 2011, alpha = 1): each vertex's primal
   *  step is the inverse of its row sum of |grad|, tau_i = 1 / sum_j sqrt(w_ij), and each
   *  edge's dual step sigma_e = 1 / (2 sqrt(w_e)), so that sigma_e sqrt(w_e) = 1/2 and
   *  the dual update needs no weight. */
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
   *  before it reads them): the duals (one per edge), grad^T y, and x-bar in single or
   *  double precision (see solve). */
  mutable Duals y;
  mutable std::vector<float> cross_terms;  ///< 3 per cross slot (EdgeArrays::cross)
  mutable Signal3 gty;
  mutable FloatSignal xbar_single;
  mutable Signal3 xbar_double;

  bool
  identity () const { return edge_ptr.empty (); }

  EdgeArrays
  edges () const
  {
    return {edge_ptr.data (), edge_col.data (), root_weight.data (), block_cross.data (),
            cross_ptr.data (),    cross_slot.data (), cross_terms.data ()};
  }

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
  // The edges: each row's entries to a later vertex, counted per row, then copied (in
  // parallel, each row to its own place).
  const std::size_t n = graph.numVertices ();
  std::vector<std::uint64_t> edge_ptr (n + 1, 0);
  detail::parallelFor (n, threads, [&] (std::size_t begin, std::size_t end) {
    for (std::size_t i = begin; i < end; ++i)
    {
      std::uint64_t later = 0;
      for (std::uint64_t e = graph.row_ptr[i]; e < graph.row_ptr[i + 1]; ++e)
        later += graph.col[e] > i;
      edge_ptr[i + 1] = later;
    }
  });
  for (std::size_t i = 0; i < n; ++i)
    edge_ptr[i + 1] += edge_ptr[i];
  const std::uint64_t num_edges = edge_ptr[n];
  detail::resizeOnHugePages (s.edge_col, num_edges);
  detail::resizeOnHugePages (s.root_weight, num_edges);
  detail::parallelFor (n, threads, [&] (std::size_t begin, std::size_t end) {
    for (std::size_t i = begin; i < end; ++i)
    {
      std::uint64_t at = edge_ptr[i];
      for (std::uint64_t e = graph.row_ptr[i]; e < graph.row_ptr[i + 1]; ++e)
        if (graph.col[e] > i)
        {
          s.edge_col[at] = graph.col[e];
          s.root_weight[at++] = std::sqrt (graph.weight[e]);
        }
    }
  });
  // The edges between blocks: their slots in edge order (each block's first), and the
  // slots into each vertex, in edge order (a counting sort).
  // (Each block's edges counted and then listed in parallel; only the edges between
  // blocks, 7% at a million points, are sorted by their other end in one pass.)
  const std::size_t num_blocks = (n + kDualBlock - 1) / kDualBlock;
  std::vector<std::uint64_t> block_cross (num_blocks + 1, 0);
  const auto forEachCross = [&] (std::size_t block, const auto &body) {
    const std::size_t end = std::min (n, (block + 1) * kDualBlock);
    for (std::uint64_t e = edge_ptr[block * kDualBlock]; e < edge_ptr[end]; ++e)
      if (s.edge_col[e] >= end)
        body (s.edge_col[e]);
  };
  detail::parallelFor (
      num_blocks, threads,
      [&] (std::size_t begin, std::size_t end) {
        for (std::size_t b = begin; b < end; ++b)
          forEachCross (b, [&] (VertexIndex) { ++block_cross[b + 1]; });
      },
      1);
  for (std::size_t b = 0; b < num_blocks; ++b)
    block_cross[b + 1] += block_cross[b];
  std::vector<VertexIndex> cross_end (block_cross[num_blocks]);  // per slot, the edge's j
  detail::parallelFor (
      num_blocks, threads,
      [&] (std::size_t begin, std::size_t end) {
        for (std::size_t b = begin; b < end; ++b)
        {
          std::uint64_t slot = block_cross[b];
          forEachCross (b, [&] (VertexIndex j) { cross_end[slot++] = j; });
        }
      },
      1);
  std::vector<std::uint64_t> cross_ptr (n + 1, 0);
  for (const VertexIndex j : cross_end)
    ++cross_ptr[j + 1];
  for (std::size_t i = 0; i < n; ++i)
    cross_ptr[i + 1] += cross_ptr[i];
  s.cross_slot.resize (cross_end.size ());
  {
    std::vector<std::uint64_t> next (cross_ptr.begin (), cross_ptr.end () - 1);
    for (std::uint64_t slot = 0; slot < cross_end.size (); ++slot)
      s.cross_slot[next[cross_end[slot]]++] = slot;
  }
  s.block_cross = std::move (block_cross);
  s.cross_ptr = std::move (cross_ptr);
  s.edge_ptr = std::move (edge_ptr);
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
  // only perturbs the dual steps. Every edge with a weight joins two vertices of one
  // component, so its difference keeps x-bar's origin out. The iterate x, the objective
  // and the gap stay in double.
  const VertexIndex *roots = component_root.empty () ? nullptr : component_root.data ();
  const auto originOf = [&] (std::size_t i) {
    return f.data () + 3 * std::size_t (roots ? roots[i] : 0);
  };
  if (gty.rows () == 0)  // the first solve; both, or neither should one fail
  {
    Duals new_y = detail::matrixOnHugePages<Duals> (static_cast<Eigen::Index> (edge_col.size ()));
    Signal3 new_gty = detail::matrixOnHugePages<Signal3> (rows);
    std::vector<float> new_cross (3 * cross_slot.size ());
    y.swap (new_y);
    gty.swap (new_gty);
    cross_terms.swap (new_cross);
  }
  // f's total variation comes with the warm start (the cold start's objective), summed
  // over the same edges.
  const EdgeArrays edges = this->edges ();
  const auto warm_kernel = [&] (std::size_t begin, std::size_t end) PCL_GRAPH_DENOISE_KERNEL {
    double variation = 0.0;
    BlockAdjoint adjoint (edges, gty.data (), begin, end);
    for (std::size_t i = begin; i < end; ++i)
      for (std::uint64_t e = edges.ptr[i]; e < edges.ptr[i + 1]; ++e)
      {
        const VertexIndex j = edges.col[e];
        const double d[3] = {f (i, 0) - f (j, 0), f (i, 1) - f (j, 1), f (i, 2) - f (j, 2)};
        const double length = std::sqrt (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
        float v[3];
        for (int c = 0; c < 3; ++c)
        {
          if (params.norm == TotalVariationNorm::ISOTROPIC)
            v[c] = length > 0.0 ? static_cast<float> (gamma * d[c] / length) : 0.0f;
          else
            v[c] = d[c] > 0.0 ? bound_gamma : (d[c] < 0.0 ? -bound_gamma : 0.0f);
          y (static_cast<Eigen::Index> (e), c) = v[c];
        }
        const float w = edges.root_weight[e];
        adjoint.add (e, w * v[0], w * v[1], w * v[2]);
        variation += double (w) * (params.norm == TotalVariationNorm::ISOTROPIC
                                       ? length
                                       : std::abs (d[0]) + std::abs (d[1]) + std::abs (d[2]));
      }
    adjoint.finish ();
    return variation;
  };
  // Sets the warm start; returns TV(f).
  const auto warmStart = [&] () {
    const double variation =
        detail::parallelSum<double> (
            n, threads,
            [&] (std::size_t begin, std::size_t end) {
              return detail::wide (warm_kernel, begin, end);
            },
            kDualBlock);
    detail::parallelFor (n, threads, [&] (std::size_t begin, std::size_t end) {
      for (std::size_t i = begin; i < end; ++i)
      {
        double cross[3];
        crossAdjoint (edges, i, cross);
        for (int c = 0; c < 3; ++c)
          x (i, c) = f (i, c) - (gty (i, c) - cross[c]);
      }
    });
    return variation;
  };
  const double f_variation = warmStart ();
  // With a gamma large against the cloud's differences the minimiser is nearly constant
  // and that start lies far from it (about gamma times the degree): then the cold start,
  // duals 0 and x = f, when the warm start's objective is more than kColdStart times
  // f's. (At the filters' derived gammas the ratio is 1-7 on noisy spheres and cubes,
  // where the warm start still converges faster and lands closer to the surface.)
  constexpr double kColdStart = 100.0;
  const double warm_objective =
      0.5 * (x - f).squaredNorm () + gamma * edgeVariation (edges, n, x, params.norm, threads);
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
          edges,
          bar,
          {y.col (0).data (), y.col (1).data (), y.col (2).data ()},
          gty.data (),
          static_cast<float> (0.5 / scale),
          bound_gamma,
          params.norm,
          pending ? x.data () : nullptr};
      return detail::parallelSum<double> (
          n, threads,
          [&] (std::size_t begin, std::size_t end) {
            const auto dual = [&] (std::size_t b, std::size_t e) PCL_GRAPH_DENOISE_KERNEL {
              return dualPass (pass, b, e);
            };
            return detail::wide (dual, begin, end);
          },
          kDualBlock);
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
      double *__restrict gtys = gty.data ();
      const double *__restrict taus = tau.data ();
      for (std::size_t i = begin; i < end; ++i)
      {
        // grad^T y completed: what the edges from earlier blocks bring (kept for the
        // gap check).
        double cross[3];
        crossAdjoint (edges, i, cross);
        const double step_i = scale * taus[i];
        const double *o = originOf (i);
        for (std::size_t c = 3 * i; c < 3 * i + 3; ++c)
        {
          gtys[c] -= cross[c - 3 * i];
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
      else if (gapMet (edgeVariation (edges, n, x, params.norm, threads)))
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

/*
 * pcl_graph_denoise: graph-signal-processing point cloud denoising for PCL.
 * SPDX-License-Identifier: BSD-3-Clause
 */
#include "aggregation.h"

#include "parallel.h"

#include <algorithm>
#include <cstdint>

namespace pcl_graph_denoise {
namespace core {
namespace detail {

namespace {

/** The damping of the Jacobi steps before and after each coarse correction. */
constexpr double kSmoothing = 0.7;

/** Coarse rows built per task: at least kMinRowsPerTask, and few enough tasks (at most
 *  kMaxTasks) that their tables of a slot per coarse vertex stay linear in the size. The
 *  rows come out the same whatever the tasks. */
constexpr std::size_t kMinRowsPerTask = 4096;
constexpr std::size_t kMaxTasks = 64;

/** A graph level as the coarsening reads it: its CSR arrays and vertex count. */
struct FineView
{
  const std::uint64_t *row_ptr;
  const VertexIndex *col;
  const float *weight;
  std::size_t size;
};

/** The entries of the coarse rows [begin, end), in the order their first fine entry
 *  comes (a fixed order: the same on any number of threads). */
struct Rows
{
  std::vector<std::uint32_t> count;
  std::vector<VertexIndex> col;
  std::vector<double> weight;  ///< summed in double: W_ab and W_ba round to the same float
};

/** log2 of an aggregate's size: the shift that takes a vertex to its aggregate. */
constexpr int
shiftOf (std::size_t aggregate)
{
  int shift = 0;
  while ((std::size_t (1) << shift) < aggregate)
    ++shift;
  return shift;
}

} // namespace

AggregationPreconditioner::AggregationPreconditioner (const PointGraph &graph,
                                                      const std::vector<double> &degree,
                                                      double g2, int num_threads)
  : g2_ (g2), num_threads_ (num_threads), linked_ (graph.numVertices ())
{
  FineView fine{graph.row_ptr.data (), graph.col.data (), graph.weight.data (),
                graph.numVertices ()};
  // A vertex's mass: how many linked vertices of the graph it stands for.
  std::vector<double> mass (fine.size);
  for (std::size_t v = 0; v < fine.size; ++v)
  {
    linked_[v] = degree[v] > 0.0;
    mass[v] = linked_[v];
  }
  static_assert ((kFirstAggregate & (kFirstAggregate - 1)) == 0 &&
                     (kAggregate & (kAggregate - 1)) == 0,
                 "aggregates of a power of two vertices (a shift finds a vertex's)");
  int shift = shiftOf (kFirstAggregate);
  while (fine.size > 0)
  {
    const std::size_t block = std::size_t (1) << shift;
    const std::size_t n = (fine.size + block - 1) / block;
    Level level;
    // Each task gathers its coarse rows' entries with a slot per coarse vertex.
    const std::size_t per_task = std::max (kMinRowsPerTask, (n + kMaxTasks - 1) / kMaxTasks);
    const std::size_t tasks = (n + per_task - 1) / per_task;
    std::vector<Rows> rows (tasks);
    parallelFor (
        n, num_threads,
        [&] (std::size_t begin, std::size_t end) {
          Rows &out = rows[begin / per_task];
          std::vector<std::uint32_t> slot (n, 0);  // 1 + the entry's position in out
          out.count.assign (end - begin, 0);
          for (std::size_t a = begin; a < end; ++a)
          {
            const std::size_t first = out.col.size ();
            for (std::size_t v = a * block; v < std::min (fine.size, (a + 1) * block); ++v)
              for (std::uint64_t e = fine.row_ptr[v]; e < fine.row_ptr[v + 1]; ++e)
              {
                const VertexIndex b = fine.col[e] >> shift;
                if (b == a)
                  continue;
                if (slot[b] <= first)
                {
                  out.col.push_back (b);
                  out.weight.push_back (0.0);
                  slot[b] = static_cast<std::uint32_t> (out.col.size ());
                }
                out.weight[slot[b] - 1] += fine.weight[e];
              }
            out.count[a - begin] = static_cast<std::uint32_t> (out.col.size () - first);
          }
        },
        per_task);
    level.row_ptr.assign (n + 1, 0);
    for (std::size_t t = 0, a = 0; t < tasks; ++t)
      for (std::uint32_t c : rows[t].count)
        level.row_ptr[a + 1] = level.row_ptr[a] + c, ++a;
    level.col.reserve (level.row_ptr[n]);
    level.weight.reserve (level.row_ptr[n]);
    for (Rows &r : rows)
    {
      level.col.insert (level.col.end (), r.col.begin (), r.col.end ());
      for (double w : r.weight)
        level.weight.push_back (static_cast<float> (w));
      r = Rows{};
    }
    std::vector<double> coarse_mass (n, 0.0);
    for (std::size_t v = 0; v < fine.size; ++v)
      coarse_mass[v >> shift] += mass[v];
    level.diagonal.resize (n);
    for (std::size_t a = 0; a < n; ++a)
    {
      double d = 0.0;
      for (std::uint64_t e = level.row_ptr[a]; e < level.row_ptr[a + 1]; ++e)
        d += level.weight[e];
      // An aggregate without linked vertices has no entries and a zero residual: any
      // positive diagonal keeps its correction zero and the operator positive definite.
      level.diagonal[a] = coarse_mass[a] > 0.0 ? coarse_mass[a] + g2 * d : 1.0;
    }
    mass.swap (coarse_mass);
    levels_.push_back (std::move (level));
    const Level &made = levels_.back ();
    if (n <= kCoarsest)
      break;
    fine = FineView{made.row_ptr.data (), made.col.data (), made.weight.data (), n};
    shift = shiftOf (kAggregate);
  }
  // Work space, and the coarsest level factorised.
  for (std::size_t l = 0; l + 1 < levels_.size (); ++l)
  {
    const auto rows = static_cast<Eigen::Index> (levels_[l].size ());
    const auto next = static_cast<Eigen::Index> (levels_[l + 1].size ());
    levels_[l].z.resize (rows, 3);
    levels_[l].rc.resize (next, 3);
    levels_[l].zc.resize (next, 3);
  }
  if (!levels_.empty ())
  {
    const Level &last = levels_.back ();
    const auto m = static_cast<Eigen::Index> (last.size ());
    Eigen::MatrixXd a = Eigen::MatrixXd::Zero (m, m);
    for (Eigen::Index i = 0; i < m; ++i)
    {
      a (i, i) = last.diagonal[i];
      for (std::uint64_t e = last.row_ptr[i]; e < last.row_ptr[i + 1]; ++e)
        a (i, last.col[e]) -= g2 * last.weight[e];
    }
    coarsest_.compute (a);
  }
}

void
AggregationPreconditioner::cycle (std::size_t l, const Coarse3 &r, Coarse3 &z) const
{
  if (l + 1 == levels_.size ())
  {
    // Each row's diagonal exceeds the sum of its other entries by the aggregate's size
    // (or 1): positive definite, and Cholesky's pivots stay at least about that.
    z = r;
    coarsest_.solveInPlace (z);
    return;
  }
  const Level &level = levels_[l];
  const std::size_t n = level.size ();
  const double g2 = g2_;
  const std::vector<double> &diagonal = level.diagonal;
  // s = sum_j w_ij u(j, .) over row i's entries.
  const auto rowSum = [&level] (std::size_t i, double (&s)[3], auto &&u) {
    for (std::uint64_t e = level.row_ptr[i]; e < level.row_ptr[i + 1]; ++e)
    {
      const double w = level.weight[e];
      const VertexIndex j = level.col[e];
      for (int c = 0; c < 3; ++c)
        s[c] += w * u (j, c);
    }
  };
  Coarse3 &y = level.z;  // the damped Jacobi step before the coarse correction
  parallelFor (n, num_threads_, [&] (std::size_t begin, std::size_t end) {
    for (std::size_t i = begin; i < end; ++i)
      y.row (i) = (kSmoothing / diagonal[i]) * r.row (i);
  });
  // rc = P^T (r - A y), aggregate by aggregate.
  const std::size_t next = levels_[l + 1].size ();
  parallelFor (next, num_threads_, [&] (std::size_t begin, std::size_t end) {
    for (std::size_t a = begin; a < end; ++a)
    {
      double rc[3] = {0.0, 0.0, 0.0};
      for (std::size_t i = a * kAggregate; i < std::min (n, (a + 1) * kAggregate); ++i)
      {
        double s[3] = {0.0, 0.0, 0.0};
        rowSum (i, s, [&y] (VertexIndex j, int c) { return y (j, c); });
        for (int c = 0; c < 3; ++c)
          rc[c] += r (i, c) - diagonal[i] * y (i, c) + g2 * s[c];
      }
      for (int c = 0; c < 3; ++c)
        level.rc (a, c) = rc[c];
    }
  });
  cycle (l + 1, level.rc, level.zc);
  // z = u + omega D^-1 (r - A u) with u = y + P zc, u formed where it is read.
  const Coarse3 &zc = level.zc;
  parallelFor (n, num_threads_, [&] (std::size_t begin, std::size_t end) {
    for (std::size_t i = begin; i < end; ++i)
    {
      const auto u = [&] (std::size_t j, int c) { return y (j, c) + zc (j / kAggregate, c); };
      double s[3] = {0.0, 0.0, 0.0};
      rowSum (i, s, u);
      for (int c = 0; c < 3; ++c)
      {
        const double ui = u (i, c);
        z (i, c) = ui + (kSmoothing / diagonal[i]) * (r (i, c) - diagonal[i] * ui + g2 * s[c]);
      }
    }
  });
}

void
AggregationPreconditioner::applyCoarse (const Coarse3 &rc, Coarse3 &zc) const
{
  if (levels_.empty ())
  {
    zc.setZero (rc.rows (), 3);
    return;
  }
  if (zc.rows () != rc.rows ())
    zc.resize (rc.rows (), 3);
  cycle (0, rc, zc);
}

} // namespace detail
} // namespace core
} // namespace pcl_graph_denoise

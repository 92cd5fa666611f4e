/*
 * pcl_graph_denoise: graph-signal-processing point cloud denoising for PCL.
 * SPDX-License-Identifier: BSD-3-Clause
 */
#include <pcl_graph_denoise/core/operators.h>

#include "components.h"
#include "huge_pages.h"
#include "parallel.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <numeric>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

namespace pcl_graph_denoise {
namespace core {

namespace {

void
requireRows (const Signal3 &signal, std::size_t rows, const char *what)
{
  if (static_cast<std::size_t> (signal.rows ()) != rows)
    throw std::invalid_argument (std::string (what) + " has the wrong number of rows");
}

/** Position of the first entry of row i whose neighbour index is above i. */
std::uint64_t
upperBegin (const PointGraph &graph, std::size_t i)
{
  const auto first = graph.col.begin () + graph.row_ptr[i];
  const auto last = graph.col.begin () + graph.row_ptr[i + 1];
  return static_cast<std::uint64_t> (
      std::upper_bound (first, last, static_cast<VertexIndex> (i)) - graph.col.begin ());
}

} // namespace

std::vector<double>
weightedDegree (const PointGraph &graph, int num_threads)
{
  const std::size_t n = graph.numVertices ();
  std::vector<double> degree;
  detail::resizeOnHugePages (degree, n);
  detail::parallelFor (n, num_threads, [&] (std::size_t begin, std::size_t end) {
    for (std::size_t i = begin; i < end; ++i)
    {
      double sum = 0.0;
      for (std::uint64_t e = graph.row_ptr[i]; e < graph.row_ptr[i + 1]; ++e)
        sum += graph.weight[e];
      degree[i] = sum;
    }
  });
  return degree;
}

void
normalizeDensity (PointGraph &graph, double power, int num_threads)
{
  if (!(power >= 0.0 && power <= 1.0))
    throw std::invalid_argument ("normalizeDensity: power must be in [0, 1]");
  if (power == 0.0)
    return;
  const std::size_t n = graph.numVertices ();
  // Each vertex's degree, then in its place the vertex's scale.
  std::vector<double> scale = weightedDegree (graph, num_threads);
  double sum = 0.0;  // in vertex order: the same mean for any number of threads
  std::size_t linked = 0;
  for (const double d : scale)
    if (d > 0.0)
      sum += d, ++linked;
  if (linked == 0)
    return;
  const double mean = sum / double (linked);
  for (double &s : scale)
    s = s > 0.0 ? std::pow (std::clamp (mean / s, 1.0 / kDensityNormalizationLimit,
                                        kDensityNormalizationLimit),
                            power)
                : 1.0;
  detail::parallelFor (n, num_threads, [&] (std::size_t begin, std::size_t end) {
    for (std::size_t i = begin; i < end; ++i)
      for (std::uint64_t e = graph.row_ptr[i]; e < graph.row_ptr[i + 1]; ++e)
        graph.weight[e] =
            static_cast<float> (double (graph.weight[e]) * (scale[i] * scale[graph.col[e]]));
  });
}

void
applyLaplacian (const PointGraph &graph, const Signal3 &x, Signal3 &y, int num_threads)
{
  const std::size_t n = graph.numVertices ();
  requireRows (x, n, "applyLaplacian: x");
  y.resize (static_cast<Eigen::Index> (n), 3);
  detail::parallelFor (n, num_threads, [&] (std::size_t begin, std::size_t end) {
    for (std::size_t i = begin; i < end; ++i)
    {
      // (L x)_i = sum_j w_ij (x_i - x_j): no cancellation against a large degree term.
      double a = 0.0, b = 0.0, c = 0.0;
      const double xi0 = x (i, 0), xi1 = x (i, 1), xi2 = x (i, 2);
      for (std::uint64_t e = graph.row_ptr[i]; e < graph.row_ptr[i + 1]; ++e)
      {
        const double w = graph.weight[e];
        const VertexIndex j = graph.col[e];
        a += w * (xi0 - x (j, 0));
        b += w * (xi1 - x (j, 1));
        c += w * (xi2 - x (j, 2));
      }
      y (i, 0) = a;
      y (i, 1) = b;
      y (i, 2) = c;
    }
  });
}

std::vector<std::uint64_t>
edgeOffsets (const PointGraph &graph)
{
  const std::size_t n = graph.numVertices ();
  std::vector<std::uint64_t> offsets (n + 1, 0);
  for (std::size_t i = 0; i < n; ++i)
    offsets[i + 1] = offsets[i] + (graph.row_ptr[i + 1] - upperBegin (graph, i));
  return offsets;
}

void
applyGradient (const PointGraph &graph, const Signal3 &x, Signal3 &g, int num_threads)
{
  const std::size_t n = graph.numVertices ();
  requireRows (x, n, "applyGradient: x");
  const std::vector<std::uint64_t> offsets = edgeOffsets (graph);
  g.resize (static_cast<Eigen::Index> (offsets[n]), 3);
  detail::parallelFor (n, num_threads, [&] (std::size_t begin, std::size_t end) {
    for (std::size_t i = begin; i < end; ++i)
    {
      std::uint64_t edge = offsets[i];
      for (std::uint64_t e = upperBegin (graph, i); e < graph.row_ptr[i + 1]; ++e, ++edge)
        g.row (edge) = std::sqrt (double (graph.weight[e])) * (x.row (i) - x.row (graph.col[e]));
    }
  });
}

void
applyGradientAdjoint (const PointGraph &graph, const Signal3 &g, Signal3 &x, int num_threads)
{
  const std::size_t n = graph.numVertices ();
  const std::vector<std::uint64_t> offsets = edgeOffsets (graph);
  requireRows (g, offsets[n], "applyGradientAdjoint: g");
  x.resize (static_cast<Eigen::Index> (n), 3);
  detail::parallelFor (n, num_threads, [&] (std::size_t begin, std::size_t end) {
    for (std::size_t i = begin; i < end; ++i)
    {
      Eigen::RowVector3d sum = Eigen::RowVector3d::Zero ();
      const VertexIndex vi = static_cast<VertexIndex> (i);
      const std::uint64_t upper = upperBegin (graph, i);
      for (std::uint64_t e = graph.row_ptr[i]; e < graph.row_ptr[i + 1]; ++e)
      {
        const VertexIndex j = graph.col[e];
        const double s = std::sqrt (double (graph.weight[e]));
        if (j > vi)
        {
          // Edge (i, j): i is its first end. Entries above i are numbered in order.
          sum += s * g.row (offsets[i] + (e - upper));
        }
        else
        {
          // Edge (j, i): find i among the upper entries of row j.
          const auto first = graph.col.begin () + graph.row_ptr[j];
          const auto last = graph.col.begin () + graph.row_ptr[j + 1];
          const auto pos = std::lower_bound (first, last, vi) - graph.col.begin ();
          sum -= s * g.row (offsets[j] + (pos - upperBegin (graph, j)));
        }
      }
      x.row (i) = sum;
    }
  });
}

namespace detail {

std::vector<VertexIndex>
componentRoots (const PointGraph &graph, std::vector<std::uint8_t> *linked, int num_threads)
{
  const std::size_t n = graph.numVertices ();
  std::vector<VertexIndex> parent (n);
  std::iota (parent.begin (), parent.end (), VertexIndex (0));
  // Joins the trees of a and b under the smaller root: every root is its tree's smallest
  // vertex, so the labels do not depend on the order of the joins.
  const auto join = [&parent] (VertexIndex a, VertexIndex b) {
    const auto root = [&parent] (VertexIndex v) {
      while (parent[v] != v)
        v = parent[v] = parent[parent[v]];  // path halving
      return v;
    };
    a = root (a);
    b = root (b);
    if (a != b)
      parent[std::max (a, b)] = std::min (a, b);
  };
  if (linked)
    linked->assign (n, 0);
  // The graph is symmetric: each edge is joined once, from the row of its smaller
  // vertex (also where a row is not sorted as it should be). Blocks of consecutive
  // vertices join their inner edges in parallel (a join inside a block only touches the
  // block's own vertices) and keep their edges to later blocks, joined afterwards.
  constexpr std::size_t kBlock = std::size_t (1) << 16;
  const std::size_t num_blocks = (n + kBlock - 1) / kBlock;
  std::vector<std::vector<std::pair<VertexIndex, VertexIndex>>> outward (num_blocks);
  parallelFor (
      num_blocks, num_threads,
      [&] (std::size_t first, std::size_t last) {
        for (std::size_t b = first; b < last; ++b)
        {
          const std::size_t end = std::min (n, (b + 1) * kBlock);
          for (std::size_t i = b * kBlock; i < end; ++i)
            for (std::uint64_t e = graph.row_ptr[i]; e < graph.row_ptr[i + 1]; ++e)
            {
              if (!(graph.weight[e] > 0.0f))
                continue;
              if (linked)
                (*linked)[i] = 1;
              const VertexIndex j = graph.col[e];
              if (j <= i)
                continue;  // joined from row j (or a loop)
              if (j < end)
                join (static_cast<VertexIndex> (i), j);
              else
                outward[b].emplace_back (static_cast<VertexIndex> (i), j);
            }
        }
      },
      1);
  for (const auto &edges : outward)
    for (const auto &[i, j] : edges)
      join (i, j);
  for (std::size_t i = 0; i < n; ++i)
    parent[i] = parent[parent[i]];  // parents precede: parent[i] is already its root
  return parent;
}

} // namespace detail

GraphComponents
connectedComponents (const PointGraph &graph, int num_threads)
{
  const std::size_t n = graph.numVertices ();
  std::vector<std::uint8_t> linked;
  const std::vector<VertexIndex> root = detail::componentRoots (graph, &linked, num_threads);
  GraphComponents out;
  std::vector<std::size_t> size (n, 0);
  for (std::size_t i = 0; i < n; ++i)
  {
    out.count += root[i] == i;
    out.isolated += linked[i] == 0;
    out.largest = std::max (out.largest, ++size[root[i]]);
  }
  return out;
}

} // namespace core
} // namespace pcl_graph_denoise

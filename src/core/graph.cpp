/*
 * pcl_graph_denoise: graph-signal-processing point cloud denoising for PCL.
 * SPDX-License-Identifier: BSD-3-Clause
 */
#include <pcl_graph_denoise/core/graph.h>
#include <pcl_graph_denoise/core/memory.h>

#include <Eigen/Eigenvalues>

#include "huge_pages.h"
#include "neighbor_search.h"
#include "parallel.h"
#include "rank_sort.h"
#include "spatial_order.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <limits>
#include <memory>
#include <numeric>
#include <stdexcept>
#include <string>

namespace pcl_graph_denoise {
namespace core {

namespace {

constexpr std::size_t kBlock = 2048;

void
requireValid (bool ok, const std::string &what)
{
  if (!ok)
    throw std::invalid_argument (what);
}

/** Smallest extent of points that do not all coincide along the longest axis: below it
 *  the squared distances between neighbours fall among single precision's subnormals
 *  (below 1.2e-38) or to 0, and the derived scales with them. */
constexpr double kMinExtent = 1e-15;

void
validatePoints (const PointMatrix &points)
{
  requireValid (static_cast<std::uint64_t> (points.rows ()) <
                    std::numeric_limits<VertexIndex>::max (),
                "too many points for 32-bit vertex indices");
  requireValid (points.allFinite (), "points must be finite");
  if (points.rows () == 0)
    return;
  const double span = (points.colwise ().maxCoeff ().cast<double> () -
                       points.colwise ().minCoeff ().cast<double> ())
                          .maxCoeff ();
  // Too wide and the squared distances overflow; too narrow (but not a single position)
  // and they underflow.
  const bool wide = !(span <= kMaxPointExtent), narrow = span > 0.0 && span < kMinExtent;
  if (wide || narrow)
  {
    char text[200];
    std::snprintf (text, sizeof (text),
                   "the points span %s%g units along an axis, %s than %g: their squared "
                   "distances would %s single precision%s",
                   narrow ? "only " : "", span, wide ? "more" : "less",
                   wide ? kMaxPointExtent : kMinExtent, wide ? "overflow" : "underflow",
                   narrow ? " (scale the cloud up)" : "");
    throw std::invalid_argument (text);
  }
}

void
validateThreads (int num_threads)
{
  requireValid (num_threads >= 0, "num_threads must be >= 0");
}

void
validateLength (double value, const char *name)
{
  requireValid (std::isfinite (value) && value >= 0.0,
                std::string (name) + " must be finite and >= 0");
}

/** Out-going neighbour lists of a directed graph, CSR-like. */
struct DirectedLists
{
  std::vector<std::uint64_t> ptr;
  std::vector<VertexIndex> idx;
};

double
squaredDistance (const PointMatrix &p, VertexIndex i, VertexIndex j)
{
  const double dx = double (p (i, 0)) - double (p (j, 0));
  const double dy = double (p (i, 1)) - double (p (j, 1));
  const double dz = double (p (i, 2)) - double (p (j, 2));
  return dx * dx + dy * dy + dz * dz;
}

/** Rows whose weights symmetrise computes at once. */
constexpr std::size_t kWeightedRows = 64;

/** Below this exponent the Gaussian weight is 0 (single-precision exp of less would be
 *  subnormal). */
constexpr float kLowestExponent = -87.0f;

/** The Gaussian weights exp(-d2 / (2 sigma^2)) of `count` squared lengths (as
 *  gaussianWeight): the exponents in double precision, their exponentials all at once
 *  in single precision with Eigen's vectorised exp (within an ulp of std::exp; one call
 *  of std::exp per edge was a tenth of the k-NN graph's construction). */
void
gaussianWeights (const double *squared_distances, std::size_t count, double sigma, float *weights)
{
  const double scale =
      sigma > 0.0 ? -0.5 / (sigma * sigma) : -std::numeric_limits<double>::infinity ();
  for (std::size_t e = 0; e < count; ++e)
    weights[e] = squared_distances[e] > 0.0 ? static_cast<float> (squared_distances[e] * scale)
                                            : 0.0f;
  auto w = Eigen::Map<Eigen::ArrayXf> (weights, static_cast<Eigen::Index> (count));
  w = (w < kLowestExponent).select (0.0f, w.exp ());
}

/** Longest row of a directed graph that symmetrise scans for a link instead of sorting
 *  it and bisecting: at k = 10, scanning the rows as the search left them took a third
 *  less time than sorting them first (100,000 and 1,000,000 points). */
constexpr std::uint64_t kScannedRow = 32;

/** Union of a directed graph and its transpose (edge if i->j or j->i), weighted by
 *  the Gaussian of the edge length. The rows of `directed` hold no vertex twice; the
 *  longer ones are sorted here. Rows come out sorted, without duplicates. The graph's
 *  columns take over `directed.idx`'s storage (room reserved there beyond its links saves
 *  a copy); `directed` is left empty. */
void
symmetrise (const PointMatrix &points, DirectedLists &directed, double sigma, int num_threads,
            PointGraph &graph)
{
  const std::size_t n = static_cast<std::size_t> (points.rows ());
  const auto bisected = [&] (std::size_t row) {
    return directed.ptr[row + 1] - directed.ptr[row] > kScannedRow;
  };
  detail::parallelFor (
      n, num_threads,
      [&] (std::size_t begin, std::size_t end) {
        for (std::size_t i = begin; i < end; ++i)
          if (bisected (i))
            std::sort (directed.idx.begin () + directed.ptr[i],
                       directed.idx.begin () + directed.ptr[i + 1]);
      },
      kBlock);
  const auto has = [&] (std::size_t row, VertexIndex j) {
    const std::uint64_t first = directed.ptr[row], last = directed.ptr[row + 1];
    if (bisected (row))
      return std::binary_search (directed.idx.begin () + first, directed.idx.begin () + last, j);
    bool found = false;  // no early exit: a branch-free loop over a short row
    for (std::uint64_t e = first; e < last; ++e)
      found |= directed.idx[e] == j;
    return found;
  };

  // Most k-NN links are mutual: only the others add an entry to the row they point
  // to. Each block of rows lists its own on all threads (written whether kept or not,
  // the count advancing only for the kept: no branch on a link), then one pass counts
  // them per row they point to and another places them, in block order.
  std::vector<std::vector<std::uint64_t>> one_way ((n + kBlock - 1) / kBlock);  // (i << 32) | j
  detail::parallelFor (
      n, num_threads,
      [&] (std::size_t begin, std::size_t end) {
        auto &links = one_way[begin / kBlock];
        std::size_t kept = 0;
        for (std::size_t i = begin; i < end; ++i)
        {
          const std::uint64_t first = directed.ptr[i], last = directed.ptr[i + 1];
          if (links.size () < kept + (last - first))
            links.resize (2 * (kept + (last - first)));
          for (std::uint64_t e = first; e < last; ++e)
          {
            const VertexIndex j = directed.idx[e];
            links[kept] = (std::uint64_t (i) << 32) | j;
            kept += !has (j, static_cast<VertexIndex> (i));
          }
        }
        links.resize (kept);
        links.shrink_to_fit ();
      },
      kBlock);
  // Row i: its out-going links, then the others' links to it. The latter, for all rows
  // in row order, are placed apart first: row i's start at row_ptr[i] - directed.ptr[i].
  std::vector<std::uint32_t> extra (n, 0);
  for (const auto &links : one_way)
    for (const std::uint64_t link : links)
      ++extra[static_cast<VertexIndex> (link)];
  graph.row_ptr.assign (n + 1, 0);
  for (std::size_t i = 0; i < n; ++i)
  {
    graph.row_ptr[i + 1] = graph.row_ptr[i] + (directed.ptr[i + 1] - directed.ptr[i]) + extra[i];
    extra[i] = 0;
  }
  std::vector<VertexIndex> incoming (graph.row_ptr[n] - directed.ptr[n]);
  for (auto &links : one_way)
  {
    for (const std::uint64_t link : links)
    {
      const auto j = static_cast<VertexIndex> (link);
      incoming[graph.row_ptr[j] - directed.ptr[j] + extra[j]++] =
          static_cast<VertexIndex> (link >> 32);
    }
    std::vector<std::uint64_t> ().swap (links);
  }
  // The out-going links move within their storage to their rows' places, the last row
  // first: no row moves towards the front, so none overwrites one yet to move.
  graph.col = std::move (directed.idx);
  detail::resizeOnHugePages (graph.col, graph.row_ptr[n]);
  for (std::size_t i = n; i-- > 0;)
    if (graph.row_ptr[i] != directed.ptr[i])
      std::copy_backward (graph.col.begin () + directed.ptr[i],
                          graph.col.begin () + directed.ptr[i + 1],
                          graph.col.begin () + graph.row_ptr[i] +
                              (directed.ptr[i + 1] - directed.ptr[i]));
  detail::resizeOnHugePages (graph.weight, graph.row_ptr[n]);
  detail::parallelFor (
      n, num_threads,
      [&] (std::size_t begin, std::size_t end) {
        // The rows' squared lengths first, then their weights all at once, a few rows
        // at a time.
        std::vector<double> squared;
        for (std::size_t chunk = begin; chunk < end; chunk += kWeightedRows)
        {
          const std::size_t chunk_end = std::min (end, chunk + kWeightedRows);
          const std::uint64_t first = graph.row_ptr[chunk];
          squared.resize (graph.row_ptr[chunk_end] - first);
          for (std::size_t i = chunk; i < chunk_end; ++i)
          {
            const std::uint64_t out = directed.ptr[i + 1] - directed.ptr[i];
            VertexIndex *const row = graph.col.data () + graph.row_ptr[i];
            const std::size_t size = graph.row_ptr[i + 1] - graph.row_ptr[i];
            const auto from = incoming.begin () + (graph.row_ptr[i] - directed.ptr[i]);
            std::copy (from, from + (size - out), row + out);
            detail::smallestFirst (row, size, size);  // sorts the row
            for (std::uint64_t e = graph.row_ptr[i]; e < graph.row_ptr[i + 1]; ++e)
              squared[e - first] =
                  squaredDistance (points, static_cast<VertexIndex> (i), graph.col[e]);
          }
          gaussianWeights (squared.data (), squared.size (), sigma, graph.weight.data () + first);
        }
      },
      kBlock);
  directed = DirectedLists ();
  // A link whose weight underflows to 0 (longer than about 13 theta: an isolated far
  // point's) carries nothing, and is left out: the rings of the quadrics and of the
  // noise estimate would reach across it.
  if (std::find (graph.weight.begin (), graph.weight.end (), 0.0f) == graph.weight.end ())
    return;
  std::uint64_t kept = 0;
  for (std::size_t i = 0; i < n; ++i)
  {
    const std::uint64_t first = graph.row_ptr[i], last = graph.row_ptr[i + 1];
    graph.row_ptr[i] = kept;
    for (std::uint64_t e = first; e < last; ++e)
      if (graph.weight[e] > 0.0f)
      {
        graph.col[kept] = graph.col[e];
        graph.weight[kept] = graph.weight[e];
        ++kept;
      }
  }
  graph.row_ptr[n] = kept;
  graph.col.resize (kept);
  graph.weight.resize (kept);
}

/** Per-point mean distance to its k nearest other points (k < n), for the vertices in
 *  `vertices` (all when it is null; the others' entries stay 0). */
std::vector<double>
meanKnnDistances (const detail::KdTree &tree, std::size_t n, int k, int num_threads,
                  const std::vector<VertexIndex> *vertices = nullptr)
{
  std::vector<double> mean (n, 0.0);
  detail::parallelFor (
      vertices ? vertices->size () : n, num_threads,
      [&] (std::size_t begin, std::size_t end) {
        std::vector<VertexIndex> idx (k), scratch_idx;
        std::vector<float> d2 (k), scratch_d2;
        for (std::size_t t = begin; t < end; ++t)
        {
          const std::size_t i = vertices ? (*vertices)[t] : t;
          tree.nearestOthers (static_cast<VertexIndex> (i), k, idx.data (), d2.data (), scratch_idx,
                              scratch_d2);
          double sum = 0.0;
          for (int m = 0; m < k; ++m)
            sum += std::sqrt (double (d2[m]));
          mean[i] = sum / k;
        }
      },
      kBlock);
  return mean;
}

/** Reorders the points along the Morton curve and records the order in `graph`; the
 *  sorted codes and their grid go to `curve` when asked (its order is left empty). */
PointMatrix
orderVertices (const PointMatrix &points, int num_threads, PointGraph &graph,
               detail::MortonSort *curve = nullptr)
{
  detail::MortonSort sorted = detail::mortonSort (points, num_threads, curve != nullptr);
  graph.order = std::move (sorted.order);
  if (curve)
  {
    curve->codes = std::move (sorted.codes);
    curve->grid = sorted.grid;
  }
  return detail::reorderPoints (points, graph.order);
}

} // namespace

std::size_t
PointGraph::memoryBytes () const
{
  return row_ptr.size () * sizeof (std::uint64_t) + col.size () * sizeof (VertexIndex) +
         weight.size () * sizeof (float) + order.size () * sizeof (VertexIndex);
}

float
gaussianWeight (double squared_distance, double sigma)
{
  float weight;
  gaussianWeights (&squared_distance, 1, sigma, &weight);
  return weight;
}

DistinctPoints
distinctPoints (const PointMatrix &points)
{
  const auto n = static_cast<std::size_t> (points.rows ());
  DistinctPoints out;
  out.of_row.resize (n);
  // Open addressing over the positions' bits (-0 read as 0), filled in row order: each
  // row finds the first row at its position, or becomes one.
  const auto bits = [&] (std::size_t row, int c) {
    const float v = points (static_cast<Eigen::Index> (row), c) + 0.0f;  // -0 + 0 = +0
    std::uint32_t b;
    std::memcpy (&b, &v, sizeof b);
    return b;
  };
  std::size_t size = 16;
  while (size < 2 * n)
    size *= 2;
  constexpr VertexIndex kEmpty = std::numeric_limits<VertexIndex>::max ();
  std::vector<VertexIndex> slot (size, kEmpty);
  std::vector<VertexIndex> firsts;  // the first row of each distinct position
  for (std::size_t row = 0; row < n; ++row)
  {
    std::uint64_t h = bits (row, 0);
    h = (h * 0x9E3779B97F4A7C15ULL) ^ bits (row, 1);
    h = (h * 0x9E3779B97F4A7C15ULL) ^ bits (row, 2);
    h *= 0x9E3779B97F4A7C15ULL;
    for (std::size_t s = (h >> 32) & (size - 1);; s = (s + 1) & (size - 1))
    {
      const VertexIndex other = slot[s];
      if (other == kEmpty)
      {
        slot[s] = static_cast<VertexIndex> (row);
        out.of_row[row] = static_cast<VertexIndex> (firsts.size ());
        firsts.push_back (static_cast<VertexIndex> (row));
        break;
      }
      if (bits (other, 0) == bits (row, 0) && bits (other, 1) == bits (row, 1) &&
          bits (other, 2) == bits (row, 2))
      {
        out.of_row[row] = out.of_row[other];
        break;
      }
    }
  }
  out.copies = n - firsts.size ();
  if (out.copies == 0)
    return out;
  out.points.resize (static_cast<Eigen::Index> (firsts.size ()), 3);
  for (std::size_t d = 0; d < firsts.size (); ++d)
    out.points.row (static_cast<Eigen::Index> (d)) = points.row (firsts[d]);
  return out;
}

PointGraph
buildKnnGraph (const PointMatrix &points, const KnnGraphParams &params)
{
  requireValid (params.k >= 1, "k must be >= 1");
  validateLength (params.sigma, "sigma");
  validateThreads (params.num_threads);
  validatePoints (points);

  PointGraph graph;
  detail::MortonSort sorted;
  const PointMatrix ordered = orderVertices (points, params.num_threads, graph, &sorted);
  const std::size_t n = graph.order.size ();
  graph.row_ptr.assign (n + 1, 0);
  if (n < 2)
    return graph;

  const int k = static_cast<int> (std::min<std::size_t> (params.k, n - 1));
  requireMemory (knnGraphMemory (n, static_cast<std::size_t> (k)), params.memory_limit,
                 "the k-NN graph of " + std::to_string (n) + " points with k = " +
                     std::to_string (k));
  DirectedLists directed;
  directed.ptr.resize (n + 1);
  for (std::size_t i = 0; i <= n; ++i)
    directed.ptr[i] = static_cast<std::uint64_t> (i) * k;
  // Room for the symmetrisation's one-way links too (a fifth of the links at k = 10 on
  // surfaces): reserved, not touched, until they come.
  detail::reserveOnHugePages (directed.idx, n * static_cast<std::size_t> (k) * 3 / 2);
  detail::resizeOnHugePages (directed.idx, n * static_cast<std::size_t> (k));
  std::vector<double> mean (n);
  detail::allNearestOthers (ordered, sorted, k, params.num_threads, directed.idx.data (),
                            mean.data ());
  std::vector<std::uint64_t> ().swap (sorted.codes);
  graph.spacing = detail::meanSpacing (mean);
  graph.sigma = params.sigma > 0.0 ? params.sigma : graph.spacing / std::sqrt (2.0);
  symmetrise (ordered, directed, graph.sigma, params.num_threads, graph);
  return graph;
}

PointGraph
buildSpatioTemporalGraph (const std::vector<PointMatrix> &frames,
                          const SpatioTemporalGraphParams &params)
{
  requireValid (params.k_spatial >= 1, "k_spatial (k1) must be >= 1");
  requireValid (params.k_temporal >= 0, "k_temporal (k2) must be >= 0");
  requireValid (params.window >= 0, "window must be >= 0");
  validateLength (params.sigma, "sigma");
  validateThreads (params.num_threads);

  // All frames in one matrix, frame 0's rows first.
  const std::size_t num_frames = frames.size ();
  std::vector<std::size_t> offset (num_frames + 1, 0);
  for (std::size_t f = 0; f < num_frames; ++f)
    offset[f + 1] = offset[f] + static_cast<std::size_t> (frames[f].rows ());
  const std::size_t n = offset[num_frames];
  requireValid (n < std::numeric_limits<VertexIndex>::max (),
                "too many points for 32-bit vertex indices");
  PointMatrix all (static_cast<Eigen::Index> (n), 3);
  for (std::size_t f = 0; f < num_frames; ++f)
    if (frames[f].rows () > 0)
      all.middleRows (static_cast<Eigen::Index> (offset[f]), frames[f].rows ()) = frames[f];
  validatePoints (all);

  PointGraph graph;
  const PointMatrix ordered = orderVertices (all, params.num_threads, graph);
  graph.row_ptr.assign (n + 1, 0);
  if (n == 0)
    return graph;

  // Each frame's vertices (ascending), its own points and k-d tree; a vertex's frame
  // and its place among the frame's vertices.
  std::vector<std::uint32_t> frame_of (n);
  std::vector<VertexIndex> local_of (n);
  std::vector<std::vector<VertexIndex>> members (num_frames);
  for (std::size_t v = 0; v < n; ++v)
  {
    const auto f = static_cast<std::uint32_t> (
        std::upper_bound (offset.begin (), offset.end (), std::size_t (graph.order[v])) -
        offset.begin () - 1);
    frame_of[v] = f;
    local_of[v] = static_cast<VertexIndex> (members[f].size ());
    members[f].push_back (static_cast<VertexIndex> (v));
  }
  std::vector<std::unique_ptr<detail::KdTree>> trees (num_frames);
  std::vector<PointMatrix> frame_points (num_frames);
  for (std::size_t f = 0; f < num_frames; ++f)
  {
    const std::size_t m = members[f].size ();
    if (m == 0)
      continue;
    frame_points[f].resize (static_cast<Eigen::Index> (m), 3);
    for (std::size_t r = 0; r < m; ++r)
      frame_points[f].row (static_cast<Eigen::Index> (r)) = ordered.row (members[f][r]);
    trees[f].reset (new detail::KdTree (frame_points[f]));
  }
  const auto spatial_k = [&] (std::size_t f) {
    return static_cast<int> (
        std::min<std::size_t> (params.k_spatial, members[f].empty () ? 0 : members[f].size () - 1));
  };
  const auto temporal_k = [&] (std::size_t g) {
    return static_cast<int> (std::min<std::size_t> (params.k_temporal, members[g].size ()));
  };
  // The frames linked to frame f, and the out-going edges of each of its vertices.
  std::vector<std::vector<std::size_t>> links (num_frames);
  std::vector<std::size_t> row_length (num_frames, 0);
  std::size_t total = 0;
  const std::size_t w = static_cast<std::size_t> (params.window);
  for (std::size_t f = 0; f < num_frames; ++f)
  {
    row_length[f] = static_cast<std::size_t> (spatial_k (f));
    for (std::size_t g = f > w ? f - w : 0; g <= std::min (num_frames - 1, f + w); ++g)
      if (g != f && temporal_k (g) > 0)
      {
        links[f].push_back (g);
        row_length[f] += static_cast<std::size_t> (temporal_k (g));
      }
    total += members[f].size () * row_length[f];
  }
  requireMemory (knnGraphMemory (n, (total + n - 1) / n), params.memory_limit,
                 "the spatio-temporal graph of " + std::to_string (n) + " points in " +
                     std::to_string (num_frames) + " frames");

  DirectedLists directed;
  directed.ptr.assign (n + 1, 0);
  for (std::size_t v = 0; v < n; ++v)
    directed.ptr[v + 1] = directed.ptr[v] + row_length[frame_of[v]];
  directed.idx.resize (directed.ptr[n]);
  std::vector<double> mean_spatial (n, 0.0);
  detail::parallelFor (
      n, params.num_threads,
      [&] (std::size_t begin, std::size_t end) {
        std::vector<VertexIndex> found, scratch_idx;
        std::vector<float> d2, scratch_d2;
        for (std::size_t v = begin; v < end; ++v)
        {
          const std::size_t f = frame_of[v];
          VertexIndex *out = directed.idx.data () + directed.ptr[v];
          const int k1 = spatial_k (f);
          if (k1 > 0)
          {
            found.resize (static_cast<std::size_t> (k1));
            d2.resize (static_cast<std::size_t> (k1));
            trees[f]->nearestOthers (local_of[v], k1, found.data (), d2.data (), scratch_idx,
                                     scratch_d2);
            double sum = 0.0;
            for (int m = 0; m < k1; ++m)
            {
              *out++ = members[f][found[m]];
              sum += std::sqrt (double (d2[m]));
            }
            mean_spatial[v] = sum / k1;
          }
          const float *query = ordered.row (static_cast<Eigen::Index> (v)).data ();
          for (const std::size_t g : links[f])
          {
            const int k2 = temporal_k (g);
            found.resize (static_cast<std::size_t> (k2));
            d2.resize (static_cast<std::size_t> (k2));
            const std::size_t got = trees[g]->nearest (query, k2, found.data (), d2.data ());
            for (std::size_t m = 0; m < got; ++m)
              *out++ = members[g][found[m]];
          }
        }
      },
      kBlock);

  std::vector<double> spatial_means;
  for (std::size_t v = 0; v < n; ++v)
    if (spatial_k (frame_of[v]) > 0)
      spatial_means.push_back (mean_spatial[v]);
  graph.spacing = detail::meanSpacing (spatial_means);
  if (spatial_means.empty () && !directed.idx.empty ())
  {
    // Every frame holds one point: the spacing is the mean length of the temporal links.
    double sum = 0.0;
    for (std::size_t v = 0; v < n; ++v)
      for (std::uint64_t e = directed.ptr[v]; e < directed.ptr[v + 1]; ++e)
        sum += std::sqrt (squaredDistance (ordered, static_cast<VertexIndex> (v), directed.idx[e]));
    graph.spacing = sum / double (directed.idx.size ());
  }
  graph.sigma = params.sigma > 0.0 ? params.sigma : graph.spacing / std::sqrt (2.0);
  symmetrise (ordered, directed, graph.sigma, params.num_threads, graph);
  return graph;
}

namespace {

/** What both uses of the epsilon-graph share: parameters checked, points in Morton
 *  order, the spacing, theta and epsilon derived, and a k-d tree to search. */
struct RadiusSearch
{
  PointGraph graph;  // order, spacing and sigma set; no edges yet
  PointMatrix ordered;
  double radius = 0.0;
  std::unique_ptr<detail::KdTree> tree;
  std::vector<double> mean_knn;  // per vertex (graph order; 0 off the queries)
  /** The query vertices in graph order (the rows below RadiusGraphParams::query_rows),
   *  empty when every vertex is one. */
  std::vector<VertexIndex> queries;
  std::size_t num_queries = 0;  // rows that are queries
  /** Exact copies (graph order): the vertices at one position have the same
   *  neighbours; the first query at each is searched, the others take its results.
   *  Empty without copies. */
  std::vector<VertexIndex> position_of;  ///< per vertex, its distinct position
  std::vector<VertexIndex> first_query;  ///< per distinct position (none: kNoVertex)
  std::vector<VertexIndex> firsts;       ///< the first queries, ascending

  bool
  isQuery (std::size_t vertex) const { return graph.order[vertex] < num_queries; }

  /** Whether a query vertex takes another's results (an exact copy of it). */
  bool
  copied (std::size_t vertex) const
  {
    return !first_query.empty () && first_query[position_of[vertex]] != vertex;
  }

  /** The first query at a copied vertex's position. */
  VertexIndex
  firstCopy (std::size_t vertex) const { return first_query[position_of[vertex]]; }
};

/** The mean distance of each distinct position among the queries (search.firsts) to
 *  its spacing_k nearest others, in the order of search.firsts, when there are exact
 *  copies: the copies do not make the surface denser (counted, a stack of copies at one
 *  position lowered the spacing, and when at least half of the points have spacing_k
 *  copies or more it was 0, and so would be epsilon and theta). Zeros when there are
 *  fewer than two distinct positions. */
std::vector<double>
distinctMeanKnn (const RadiusSearch &search, const RadiusGraphParams &params)
{
  PointMatrix points (static_cast<Eigen::Index> (search.firsts.size ()), 3);
  for (std::size_t r = 0; r < search.firsts.size (); ++r)
    points.row (static_cast<Eigen::Index> (r)) = search.ordered.row (search.firsts[r]);
  const auto m = static_cast<std::size_t> (points.rows ());
  if (m < 2)
    return std::vector<double> (m, 0.0);
  const detail::KdTree tree (points);
  const int k = static_cast<int> (std::min<std::size_t> (params.spacing_k, m - 1));
  return meanKnnDistances (tree, m, k, params.num_threads);
}

/** The search of an epsilon-radius graph; `queries` false: every row is a query (the
 *  graph itself), true: the first params.query_rows rows are. */
RadiusSearch
prepareRadiusSearch (const PointMatrix &points, const RadiusGraphParams &params, bool queries)
{
  validateLength (params.radius, "radius");
  validateLength (params.sigma, "sigma");
  requireValid (std::isfinite (params.radius_factor) && params.radius_factor > 0.0,
                "radius_factor must be finite and > 0");
  requireValid (std::isfinite (params.sigma_factor) && params.sigma_factor > 0.0,
                "sigma_factor must be finite and > 0");
  requireValid (params.spacing_k >= 1, "spacing_k must be >= 1");
  validateThreads (params.num_threads);
  validatePoints (points);

  const auto rows = static_cast<std::size_t> (points.rows ());
  requireValid (params.query_rows <= rows, "query_rows must be at most the number of points");

  RadiusSearch search;
  search.ordered = orderVertices (points, params.num_threads, search.graph);
  const std::size_t n = search.graph.order.size ();
  search.num_queries = queries && params.query_rows > 0 ? params.query_rows : n;
  search.graph.row_ptr.assign (n + 1, 0);
  search.radius = params.radius;
  if (n < 2)
    return search;
  if (search.num_queries < n)
    for (std::size_t v = 0; v < n; ++v)
      if (search.isQuery (v))
        search.queries.push_back (static_cast<VertexIndex> (v));
  search.tree.reset (new detail::KdTree (search.ordered));
  const int k = static_cast<int> (std::min<std::size_t> (params.spacing_k, n - 1));
  // Exact copies: one search per position (m copies of a driver's invalid (0, 0, 0)
  // would otherwise each scan the m - 1 others: 30,000 took 24 s).
  {
    DistinctPoints distinct = distinctPoints (search.ordered);
    if (distinct.copies > 0)
    {
      constexpr VertexIndex kNoVertex = std::numeric_limits<VertexIndex>::max ();
      search.position_of = std::move (distinct.of_row);
      search.first_query.assign (static_cast<std::size_t> (distinct.points.rows ()), kNoVertex);
      for (std::size_t v = 0; v < n; ++v)
        if (search.isQuery (v) && search.first_query[search.position_of[v]] == kNoVertex)
        {
          search.first_query[search.position_of[v]] = static_cast<VertexIndex> (v);
          search.firsts.push_back (static_cast<VertexIndex> (v));
        }
    }
  }
  const bool copies = !search.firsts.empty ();
  const std::vector<VertexIndex> *subset = search.queries.empty () ? nullptr : &search.queries;
  std::vector<double> mean;  // of the distinct query positions
  if (copies)
  {
    // Among the distinct positions: a copy is no neighbour.
    mean = distinctMeanKnn (search, params);
    search.mean_knn.assign (n, 0.0);
    for (std::size_t r = 0; r < search.firsts.size (); ++r)
      search.mean_knn[search.firsts[r]] = mean[r];
    for (std::size_t v = 0; v < n; ++v)
      if (search.isQuery (v) && search.copied (v))
        search.mean_knn[v] = search.mean_knn[search.firstCopy (v)];
  }
  else
  {
    search.mean_knn = meanKnnDistances (*search.tree, n, k, params.num_threads, subset);
    if (subset)
      for (const VertexIndex v : search.queries)
        mean.push_back (search.mean_knn[v]);
    else
      mean = search.mean_knn;
  }
  auto middle = mean.begin () + mean.size () / 2;
  std::nth_element (mean.begin (), middle, mean.end ());
  search.graph.spacing = *middle;
  search.graph.sigma =
      params.sigma > 0.0 ? params.sigma : params.sigma_factor * search.graph.spacing;
  if (params.radius == 0.0)
    search.radius = params.radius_factor * search.graph.spacing;
  return search;
}

/** Fewest neighbours whose plane gives a point a normal residual. */
constexpr std::size_t kMinPlaneNeighbours = 5;

/** Most neighbours a point's plane is fitted to: its nearest ones where its epsilon-ball
 *  holds more (a laser scan's points beside the scanner had 20,000, and fitting them all
 *  took most of the filter's time; a surface sampled evenly has about 30 within the
 *  default epsilon). */
constexpr std::size_t kMaxPlaneNeighbours = 256;

/** Most neighbours level with a point flagged off the surface: an outlier may have a
 *  companion, but three points level off a plane make a layer. */
constexpr std::size_t kMaxSupport = 1;

/** Most refits of a neighbourhood's plane without the neighbours off it. */
constexpr int kMaxRefits = 4;

/** Smallest noise scale of the residual test, in spacings: deviations below a hundredth
 *  of the spacing (rounding, quantised coordinates) count as no noise. */
constexpr double kResidualFloor = 0.01;

/** Median of the finite values of `values` (NaN when there is none). */
double
finiteMedian (std::vector<float> values)
{
  values.erase (std::remove_if (values.begin (), values.end (),
                                [] (float v) { return !std::isfinite (v); }),
                values.end ());
  if (values.empty ())
    return std::numeric_limits<double>::quiet_NaN ();
  auto middle = values.begin () + values.size () / 2;
  std::nth_element (values.begin (), middle, values.end ());
  return *middle;
}

/** The mean of `neighbors`' positions relative to `p`, and their covariance, each with
 *  its weight (`weights`: one per neighbour; null: all 1). False when the weights sum to
 *  0. Relative to `p`, so that large coordinates lose no precision. */
bool
neighbourMoments (const PointMatrix &points, const Eigen::Vector3d &p,
                  const std::vector<VertexIndex> &neighbors, const std::vector<double> *weights,
                  Eigen::Vector3d &mean, Eigen::Matrix3d &covariance)
{
  double total = 0.0;
  Eigen::Vector3d first = Eigen::Vector3d::Zero ();
  Eigen::Matrix3d second = Eigen::Matrix3d::Zero ();
  for (std::size_t m = 0; m < neighbors.size (); ++m)
  {
    const double w = weights ? (*weights)[m] : 1.0;
    const Eigen::Vector3d q = points.row (neighbors[m]).transpose ().cast<double> () - p;
    total += w;
    first += w * q;
    second.noalias () += (w * q) * q.transpose ();
  }
  if (!(total > 0.0))
    return false;
  mean = first / total;
  covariance = second / total - mean * mean.transpose ();
  return true;
}

/** The plane of a point's neighbours, itself excluded, refitted without the neighbours
 *  farther than 3 spreads from the last plane until none is (at most kMaxRefits times):
 *  a few outliers among them then neither tilt it nor widen its spread, and near a sharp
 *  edge it settles on the point's own face. */
struct PlaneFit
{
  double residual = 0.0;  ///< |n . (p - c)|: the point's distance to the plane
  double spread = 0.0;    ///< RMS distance of the neighbours to the plane
  double first_residual = 0.0;  ///< the residual from the plane of all the neighbours
  double first_spread = 0.0;    ///< the spread about that plane
  /** Neighbours about as far off the final plane as the point (closer to the point than
   *  half its residual, along the normal): it is not alone there, but on a layer, a step
   *  or the other side of an edge. */
  std::size_t support = 0;

  /** Fits the neighbours whose weight is 1, all with equal weight (`weights` holds 1 or 0
   *  per neighbour, and is overwritten). False when fewer than kMinPlaneNeighbours of
   *  them remain. */
  bool
  fit (const PointMatrix &points, VertexIndex self, const std::vector<VertexIndex> &neighbors,
       std::vector<double> &weights, double floor)
  {
    const Eigen::Vector3d p = points.row (self).transpose ().cast<double> ();
    std::size_t kept = static_cast<std::size_t> (
        std::count_if (weights.begin (), weights.end (), [] (double w) { return w > 0.0; }));
    if (kept < kMinPlaneNeighbours || !solve (points, p, neighbors, weights))
      return false;
    first_residual = residual;
    first_spread = spread;
    candidates_.assign (weights.begin (), weights.end ());
    for (int refit = 0; refit < kMaxRefits; ++refit)
    {
      const double limit = 3.0 * std::max (spread, floor);
      std::size_t dropped = 0;
      for (std::size_t m = 0; m < neighbors.size (); ++m)
        if (weights[m] > 0.0 &&
            std::abs (normal.dot (points.row (neighbors[m]).transpose ().cast<double> () - p) -
                      offset) > limit)
        {
          weights[m] = 0.0;
          ++dropped;
        }
      if (dropped == 0)
        break;
      kept -= dropped;
      if (kept < kMinPlaneNeighbours || !solve (points, p, neighbors, weights))
        return false;
    }
    support = 0;
    for (std::size_t m = 0; m < neighbors.size (); ++m)
      support += candidates_[m] > 0.0 &&
                 std::abs (normal.dot (points.row (neighbors[m]).transpose ().cast<double> () - p)) <
                     0.5 * residual;
    return true;
  }

private:
  std::vector<double> candidates_;  ///< the neighbours fitted first
  Eigen::Vector3d normal;
  double offset = 0.0;  ///< the plane's signed offset from p along the normal
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig;

  bool
  solve (const PointMatrix &points, const Eigen::Vector3d &p,
         const std::vector<VertexIndex> &neighbors, const std::vector<double> &weights)
  {
    Eigen::Vector3d mean;
    Eigen::Matrix3d covariance;
    if (!neighbourMoments (points, p, neighbors, &weights, mean, covariance))
      return false;
    eig.computeDirect (covariance);
    normal = eig.eigenvectors ().col (0);
    offset = normal.dot (mean);
    residual = std::abs (offset);
    spread = std::sqrt (std::max (eig.eigenvalues ()(0), 0.0));
    return true;
  }
};

/** A vertex's planes for the normal-residual test (NaN where it has none). */
struct PlaneResiduals
{
  float residual = std::numeric_limits<float>::quiet_NaN ();  ///< from the refitted plane
  float spread = 0.0f;
  float first_residual = 0.0f;  ///< from the plane of all the neighbours
  float first_spread = 0.0f;
  std::uint32_t support = 0;
};

/** The normal-residual test of radiusGraphDegrees (see RadiusDegrees::off_surface), on
 *  the planes of the vertices in graph order. */
void
flagOffSurface (const RadiusSearch &search, const RadiusGraphParams &params,
                const std::vector<PlaneResiduals> &planes, RadiusDegrees &out)
{
  constexpr double kMadToSigma = 1.0 / 0.6744897501960817;
  std::vector<float> residuals (planes.size ());
  for (std::size_t v = 0; v < planes.size (); ++v)
    residuals[v] = planes[v].residual;
  const double global = finiteMedian (std::move (residuals)) * kMadToSigma;
  const double floor = kResidualFloor * search.graph.spacing;
  const double s = std::isfinite (global) ? std::max (global, floor) : floor;
  const double c = params.residual_multiplier;
  out.residual_scale = s;
  for (std::size_t v = 0; v < planes.size (); ++v)
  {
    if (!search.isQuery (v))
      continue;
    const PlaneResiduals &plane = planes[v];
    out.off_surface[search.graph.order[v]] =
        plane.residual > c * std::max<double> (s, plane.spread) &&
        plane.first_residual > 0.5 * c * std::max<double> (s, plane.first_spread) &&
        plane.support <= kMaxSupport;
  }
}

/** The sparse-surface test's limits (see RadiusDegrees::sparse_surface): the largest
 *  ratio of a linked point's mean k-NN distance to its neighbour's (or to the median of
 *  its neighbours' for a start on a line), and the flatness and offset of a point that
 *  passes the link on. */
constexpr double kSparseSurfaceRatio = 1.25;
constexpr double kSparseSurfaceFlatness = 0.4;
constexpr double kSparseSurfaceOffset = 0.4;
/** A point's neighbours lie on a line when their middle standard deviation is at most
 *  this times their largest. */
constexpr double kSparseSurfaceLine = 0.1;

/** How `self` lies among `neighbours` (see RadiusDegrees::sparse_surface). */
enum class Lie : std::uint8_t
{
  APART,  ///< off their plane, or they lie on none
  PLANE,  ///< on the plane of its neighbours
  LINE,   ///< on the line of its neighbours
};

Lie
lieAmong (const PointMatrix &points, VertexIndex self, const std::vector<VertexIndex> &neighbours)
{
  Eigen::Vector3d mean;
  Eigen::Matrix3d covariance;
  if (neighbours.size () < 3 ||
      !neighbourMoments (points, points.row (self).transpose ().cast<double> (), neighbours,
                         nullptr, mean, covariance))
    return Lie::APART;
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig;
  eig.computeDirect (covariance);
  const double smallest = std::max (eig.eigenvalues ()(0), 0.0);
  const double middle = std::max (eig.eigenvalues ()(1), 0.0);
  const double largest = eig.eigenvalues ()(2);
  if (!(largest > 0.0))
    return Lie::APART;
  const double offset = eig.eigenvectors ().col (0).dot (mean);
  const double limit = kSparseSurfaceOffset * kSparseSurfaceOffset * largest;
  if (middle <= kSparseSurfaceLine * kSparseSurfaceLine * largest)
  {
    const double along = eig.eigenvectors ().col (2).dot (mean);
    if (mean.squaredNorm () - along * along <= limit)
      return Lie::LINE;
  }
  return smallest <= kSparseSurfaceFlatness * kSparseSurfaceFlatness * largest &&
                 offset * offset <= limit
             ? Lie::PLANE
             : Lie::APART;
}

/** Most points a sparse-surface query looks through for its distinct neighbours (a
 *  point beside a stack of copies finds fewer, and is judged on those). */
constexpr std::size_t kMaxSparseSurfaceSearch = 4096;

/** The nearest distinct positions of a vertex (see RadiusDegrees::sparse_surface). */
class DistinctNeighbours
{
public:
  DistinctNeighbours (const RadiusSearch &search, int k)
      : search_ (search), k_ (static_cast<std::size_t> (k))
  {
  }

  /** The k nearest distinct positions other than self's, one vertex for each, nearest
   *  first (fewer when the cloud, or the kMaxSparseSurfaceSearch nearest points, hold
   *  fewer). */
  const std::vector<VertexIndex> &
  operator() (VertexIndex self)
  {
    const std::size_t n = search_.graph.numVertices ();
    const bool copies = !search_.position_of.empty ();
    std::size_t wanted = std::min (n, k_ + 1);
    for (;;)
    {
      found_.resize (wanted);
      squared_.resize (wanted);
      const std::size_t got = search_.tree->nearest (search_.ordered.row (self).data (),
                                                     static_cast<int> (wanted), found_.data (),
                                                     squared_.data ());
      neighbors_.clear ();
      for (std::size_t m = 0; m < got && neighbors_.size () < k_; ++m)
      {
        const VertexIndex j = found_[m];
        if (j == self)
          continue;
        if (copies)
        {
          const VertexIndex position = search_.position_of[j];
          if (position == search_.position_of[self] ||
              std::any_of (neighbors_.begin (), neighbors_.end (), [&] (VertexIndex other) {
                return search_.position_of[other] == position;
              }))
            continue;
        }
        neighbors_.push_back (j);
      }
      if (neighbors_.size () >= k_ || got < wanted || wanted >= n ||
          wanted >= kMaxSparseSurfaceSearch)
        return neighbors_;
      wanted = std::min ({n, 2 * wanted, kMaxSparseSurfaceSearch});
    }
  }

private:
  const RadiusSearch &search_;
  const std::size_t k_;
  std::vector<VertexIndex> neighbors_, found_;
  std::vector<float> squared_;
};

/** The sparse-surface test of radiusGraphDegrees (see RadiusDegrees::sparse_surface),
 *  once the degrees are known; `mean_knn` per vertex in graph order. */
void
flagSparseSurfaces (const RadiusSearch &search, const RadiusGraphParams &params,
                    const std::vector<double> &mean_knn, RadiusDegrees &out)
{
  const std::size_t n = search.graph.numVertices ();
  const double threshold =
      automaticDegreeThreshold (out.degree, params.sparse_surface_ratio).threshold;
  const auto degree = [&] (std::size_t v) { return out.degree[search.graph.order[v]]; };
  // The points the growth may reach: the first query at each position below the
  // threshold, or sparser than the cloud's typical point; the others it starts from.
  const double dense = kSparseSurfaceRatio * search.graph.spacing;
  constexpr VertexIndex kNone = std::numeric_limits<VertexIndex>::max ();
  std::vector<VertexIndex> candidates, slot (n, kNone);
  for (std::size_t v = 0; v < n; ++v)
    if (search.isQuery (v) && !search.copied (v) && (degree (v) < threshold || mean_knn[v] > dense))
    {
      slot[v] = static_cast<VertexIndex> (candidates.size ());
      candidates.push_back (static_cast<VertexIndex> (v));
    }
  // Their nearest distinct positions, as a first copy where the position has queries.
  const int k = static_cast<int> (std::min<std::size_t> (params.spacing_k, n - 1));
  const auto kk = static_cast<std::size_t> (k);
  std::vector<VertexIndex> near (candidates.size () * kk, kNone);
  std::vector<Lie> lie (candidates.size (), Lie::APART);
  detail::parallelFor (
      candidates.size (), params.num_threads,
      [&] (std::size_t begin, std::size_t end) {
        DistinctNeighbours nearest (search, k);
        for (std::size_t c = begin; c < end; ++c)
        {
          const std::vector<VertexIndex> &found = nearest (candidates[c]);
          lie[c] = lieAmong (search.ordered, candidates[c], found);
          for (std::size_t m = 0; m < found.size (); ++m)
            near[c * kk + m] =
                search.isQuery (found[m]) && search.copied (found[m]) ? search.firstCopy (found[m])
                                                                      : found[m];
        }
      },
      kBlock);
  // Grow from the typical points (not candidates), through links j -> i (j among i's
  // nearest) between points of like density; a point reached passes it on when it lies on
  // its neighbours' plane. The closure does not depend on the order.
  const auto linked = [&] (VertexIndex j, VertexIndex i) {
    return search.isQuery (j) && mean_knn[i] <= kSparseSurfaceRatio * mean_knn[j];
  };
  const auto each_near = [&] (std::size_t c, const auto &visit) {
    for (std::size_t m = 0; m < kk && near[c * kk + m] != kNone; ++m)
      visit (near[c * kk + m]);
  };
  std::vector<std::uint8_t> flag (n, 0);  // graph order
  std::vector<VertexIndex> queue;
  const auto reach = [&] (VertexIndex j, std::size_t c) {
    if (!flag[candidates[c]] && linked (j, candidates[c]))
    {
      flag[candidates[c]] = 1;
      if (lie[c] != Lie::APART)
        queue.push_back (static_cast<VertexIndex> (c));
    }
  };
  // Who links to whom among the candidates (CSR: the candidates that have c among their
  // nearest), and the first steps from the typical points.
  std::vector<std::uint64_t> dependent_ptr (candidates.size () + 1, 0);
  std::vector<double> densities;
  for (std::size_t c = 0; c < candidates.size (); ++c)
  {
    // A line of points as dense as its neighbours (a far ring of a spinning scanner,
    // out of reach of the rest): a start of its own.
    if (lie[c] == Lie::LINE)
    {
      densities.clear ();
      each_near (c, [&] (VertexIndex j) {
        if (search.isQuery (j))
          densities.push_back (mean_knn[j]);
      });
      if (!densities.empty ())
      {
        auto middle = densities.begin () + densities.size () / 2;
        std::nth_element (densities.begin (), middle, densities.end ());
        if (mean_knn[candidates[c]] <= kSparseSurfaceRatio * *middle && !flag[candidates[c]])
        {
          flag[candidates[c]] = 1;
          queue.push_back (static_cast<VertexIndex> (c));
        }
      }
    }
    each_near (c, [&] (VertexIndex j) {
      if (slot[j] != kNone)
        ++dependent_ptr[slot[j] + 1];
      else
        reach (j, c);
    });
  }
  std::partial_sum (dependent_ptr.begin (), dependent_ptr.end (), dependent_ptr.begin ());
  std::vector<VertexIndex> dependents (dependent_ptr.back ());
  {
    std::vector<std::uint64_t> fill (dependent_ptr.begin (), dependent_ptr.end () - 1);
    for (std::size_t c = 0; c < candidates.size (); ++c)
      each_near (c, [&] (VertexIndex j) {
        if (slot[j] != kNone)
          dependents[fill[slot[j]]++] = static_cast<VertexIndex> (c);
      });
  }
  for (std::size_t head = 0; head < queue.size (); ++head)
    for (std::uint64_t e = dependent_ptr[queue[head]]; e < dependent_ptr[queue[head] + 1]; ++e)
      reach (candidates[queue[head]], dependents[e]);
  for (std::size_t v = 0; v < n; ++v)
    if (search.isQuery (v))
    {
      const std::size_t first = search.copied (v) ? search.firstCopy (v) : v;
      out.sparse_surface[search.graph.order[v]] = flag[first] && degree (first) < threshold;
    }
}

} // namespace

PointGraph
buildRadiusGraph (const PointMatrix &points, const RadiusGraphParams &params,
                  double *radius_used)
{
  RadiusSearch search = prepareRadiusSearch (points, params, false);
  std::vector<double> ().swap (search.mean_knn);  // only the degrees need it
  if (radius_used)
    *radius_used = search.radius;
  const std::size_t n = search.graph.numVertices ();
  if (n < 2)
    return std::move (search.graph);

  // Each block of queries fills its own slot, so the lists come out in vertex order
  // whatever the scheduling.
  const std::size_t num_blocks = (n + kBlock - 1) / kBlock;
  std::vector<std::vector<VertexIndex>> block_idx (num_blocks);
  DirectedLists directed;
  directed.ptr.assign (n + 1, 0);
  detail::parallelFor (
      n, params.num_threads,
      [&] (std::size_t begin, std::size_t end) {
        std::vector<std::pair<VertexIndex, float>> scratch;
        auto &idx = block_idx[begin / kBlock];
        for (std::size_t i = begin; i < end; ++i)
        {
          const std::size_t before = idx.size ();
          search.tree->othersWithin (static_cast<VertexIndex> (i),
                                     static_cast<float> (search.radius), idx, scratch);
          directed.ptr[i + 1] = idx.size () - before;
        }
      },
      kBlock);
  std::partial_sum (directed.ptr.begin (), directed.ptr.end (), directed.ptr.begin ());
  // A little room for links the search saw from one side only (see below).
  detail::reserveOnHugePages (directed.idx, directed.ptr[n] + directed.ptr[n] / 1024 + 64);
  for (auto &idx : block_idx)
  {
    directed.idx.insert (directed.idx.end (), idx.begin (), idx.end ());
    std::vector<VertexIndex> ().swap (idx);
  }
  // Within-radius is symmetric already; the union only guards against a pair that
  // the tree's pruning would see from one side alone.
  symmetrise (search.ordered, directed, search.graph.sigma, params.num_threads, search.graph);
  return std::move (search.graph);
}

RadiusDegrees
radiusGraphDegrees (const PointMatrix &points, const RadiusGraphParams &params)
{
  requireValid (std::isfinite (params.residual_multiplier) && params.residual_multiplier >= 0.0,
                "residual_multiplier must be finite and >= 0");
  requireValid (std::isfinite (params.sparse_surface_ratio) && params.sparse_surface_ratio >= 0.0,
                "sparse_surface_ratio must be finite and >= 0");
  RadiusSearch search = prepareRadiusSearch (points, params, true);
  RadiusDegrees out;
  out.radius = search.radius;
  out.sigma = search.graph.sigma;
  out.spacing = search.graph.spacing;
  const std::size_t n = search.graph.numVertices (), q = search.num_queries;
  out.degree.assign (q, 0.0);
  out.mean_knn_distance.assign (q, 0.0f);
  const bool residuals = params.residual_multiplier > 0.0;
  const bool sparse = params.sparse_surface_ratio > 0.0;
  if (residuals)
    out.off_surface.assign (q, 0);
  if (sparse)
    out.sparse_surface.assign (q, 0);
  if (n < 2)
    return out;
  for (std::size_t v = 0; v < n; ++v)
    if (search.isQuery (v))
      out.mean_knn_distance[search.graph.order[v]] = static_cast<float> (search.mean_knn[v]);
  if (!sparse)
    std::vector<double> ().swap (search.mean_knn);
  // The planes of the normal-residual test per vertex (graph order; the queries' only).
  const double floor = kResidualFloor * search.graph.spacing;
  std::vector<PlaneResiduals> planes (residuals ? n : 0);
  const bool every = search.queries.empty ();
  detail::parallelFor (
      every ? n : search.queries.size (), params.num_threads,
      [&] (std::size_t begin, std::size_t end) {
        std::vector<std::pair<VertexIndex, float>> scratch;
        std::vector<VertexIndex> neighbors;
        std::vector<double> weights;
        std::vector<double> squared;
        std::vector<float> gaussian;
        std::vector<std::pair<double, VertexIndex>> nearest;
        PlaneFit fit;
        for (std::size_t t = begin; t < end; ++t)
        {
          const std::size_t i = every ? t : search.queries[t];
          if (search.copied (i))
            continue;  // takes its first copy's results, below
          neighbors.clear ();
          const auto vi = static_cast<VertexIndex> (i);
          search.tree->othersWithin (vi, static_cast<float> (search.radius), neighbors, scratch);
          squared.resize (neighbors.size ());
          for (std::size_t m = 0; m < neighbors.size (); ++m)
            squared[m] = squaredDistance (search.ordered, vi, neighbors[m]);
          gaussian.resize (neighbors.size ());
          gaussianWeights (squared.data (), squared.size (), out.sigma, gaussian.data ());
          out.degree[search.graph.order[i]] =
              std::accumulate (gaussian.begin (), gaussian.end (), 0.0);
          if (!residuals)
            continue;
          // The plane leaves the point out, and so its exact copies: at its position they
          // would pass for surface points beside it in the layer rule (PlaneFit::support),
          // and an outlier copied twice would be kept. (Its degree counts them, as
          // RadiusOutlierRemoval counts them.)
          if (!search.position_of.empty ())
          {
            const VertexIndex own = search.position_of[i];
            std::size_t kept = 0;
            for (std::size_t m = 0; m < neighbors.size (); ++m)
              if (search.position_of[neighbors[m]] != own)
              {
                neighbors[kept] = neighbors[m];
                squared[kept++] = squared[m];
              }
            neighbors.resize (kept);
            squared.resize (kept);
          }
          if (neighbors.size () > kMaxPlaneNeighbours)
          {
            // The nearest, by (distance, index): a choice that depends on nothing else.
            nearest.resize (neighbors.size ());
            for (std::size_t m = 0; m < neighbors.size (); ++m)
              nearest[m] = {squared[m], neighbors[m]};
            std::nth_element (nearest.begin (), nearest.begin () + kMaxPlaneNeighbours,
                              nearest.end ());
            neighbors.resize (kMaxPlaneNeighbours);
            for (std::size_t m = 0; m < kMaxPlaneNeighbours; ++m)
              neighbors[m] = nearest[m].second;
          }
          weights.assign (neighbors.size (), 1.0);
          if (fit.fit (search.ordered, vi, neighbors, weights, floor))
          {
            planes[i].residual = static_cast<float> (fit.residual);
            planes[i].spread = static_cast<float> (fit.spread);
            planes[i].first_residual = static_cast<float> (fit.first_residual);
            planes[i].first_spread = static_cast<float> (fit.first_spread);
            planes[i].support = static_cast<std::uint32_t> (fit.support);
          }
        }
      },
      kBlock);
  if (!search.first_query.empty ())
    for (std::size_t v = 0; v < n; ++v)
      if (search.isQuery (v) && search.copied (v))
      {
        const VertexIndex first = search.firstCopy (v);
        out.degree[search.graph.order[v]] = out.degree[search.graph.order[first]];
        if (residuals)
          planes[v] = planes[first];
      }
  if (residuals)
    flagOffSurface (search, params, planes, out);
  if (sparse)
    flagSparseSurfaces (search, params, search.mean_knn, out);
  return out;
}

DegreeThreshold
automaticDegreeThreshold (const std::vector<double> &degree, double ratio)
{
  requireValid (std::isfinite (ratio) && ratio >= 0.0, "the threshold ratio must be finite and >= 0");
  DegreeThreshold out;
  if (degree.empty ())
    return out;
  std::vector<double> sorted = degree;
  std::nth_element (sorted.begin (), sorted.begin () + sorted.size () / 4, sorted.end ());
  double quartile = sorted[sorted.size () / 4];
  if (quartile == 0.0 && ratio > 0.0)
  {
    sorted.erase (std::remove (sorted.begin (), sorted.end (), 0.0), sorted.end ());
    out.without_neighbour = degree.size () - sorted.size ();
    if (!sorted.empty ())
    {
      std::nth_element (sorted.begin (), sorted.begin () + sorted.size () / 4, sorted.end ());
      quartile = sorted[sorted.size () / 4];
    }
  }
  out.threshold = ratio * quartile;
  return out;
}

} // namespace core
} // namespace pcl_graph_denoise

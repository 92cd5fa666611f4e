/*
 * pcl_graph_denoise: graph-signal-processing point cloud denoising for PCL.
 * SPDX-License-Identifier: BSD-3-Clause
 *
 * The numerical core against brute force on seeded random clouds.
 */
#include <pcl_graph_denoise/core/graph.h>
#include <pcl_graph_denoise/core/normals.h>
#include <pcl_graph_denoise/core/operators.h>

#include "components.h"
#include "wide_kernels.h"
#include "synthetic.h"
#include "test_clouds.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <functional>
#include <limits>
#include <map>
#include <numeric>
#include <random>
#include <set>
#include <stdexcept>
#include <string>

using namespace pcl_graph_denoise::core;
namespace synthetic = pcl_graph_denoise::synthetic;

namespace {

PointMatrix
randomPoints (int n, std::uint64_t seed, float scale = 1.0f)
{
  std::mt19937_64 rng (seed);
  std::uniform_real_distribution<float> u (-1.0f, 1.0f);
  PointMatrix p (n, 3);
  for (int i = 0; i < n; ++i)
    for (int d = 0; d < 3; ++d)
      p (i, d) = scale * u (rng);
  return p;
}

Signal3
randomSignal (std::size_t n, std::uint64_t seed)
{
  std::mt19937_64 rng (seed);
  std::normal_distribution<double> g;
  Signal3 x (n, 3);
  for (Eigen::Index i = 0; i < x.rows (); ++i)
    for (int d = 0; d < 3; ++d)
      x (i, d) = g (rng);
  return x;
}

double
dist2 (const PointMatrix &p, int i, int j)
{
  return (p.row (i).cast<double> () - p.row (j).cast<double> ()).squaredNorm ();
}

/** Brute-force k nearest other points, by (distance, index). */
std::vector<std::vector<int>>
bruteKnn (const PointMatrix &p, int k)
{
  const int n = static_cast<int> (p.rows ());
  std::vector<std::vector<int>> out (n);
  for (int i = 0; i < n; ++i)
  {
    std::vector<std::pair<double, int>> all;
    for (int j = 0; j < n; ++j)
      if (j != i)
        all.emplace_back (dist2 (p, i, j), j);
    std::sort (all.begin (), all.end ());
    for (int m = 0; m < k; ++m)
      out[i].push_back (all[m].second);
  }
  return out;
}

/** The graph's edges as a map from (caller's i, caller's j) to weight. */
std::map<std::pair<int, int>, float>
edgesInCallerOrder (const PointGraph &g)
{
  std::map<std::pair<int, int>, float> edges;
  for (std::size_t v = 0; v < g.numVertices (); ++v)
    for (auto e = g.row_ptr[v]; e < g.row_ptr[v + 1]; ++e)
      edges[{int (g.order[v]), int (g.order[g.col[e]])}] = g.weight[e];
  return edges;
}

void
expectSameGraph (const PointGraph &a, const PointGraph &b)
{
  EXPECT_EQ (a.order, b.order);
  EXPECT_EQ (a.row_ptr, b.row_ptr);
  EXPECT_EQ (a.col, b.col);
  EXPECT_EQ (a.weight, b.weight);
  EXPECT_EQ (a.sigma, b.sigma);
  EXPECT_EQ (a.spacing, b.spacing);
}

/** Every row of g strictly increasing: sorted, and no neighbour stored twice (an edge
 *  set, as edgesInCallerOrder builds, would hide a repeat). */
void
expectRowsSortedWithoutRepeats (const PointGraph &g, const std::string &what)
{
  for (std::size_t v = 0; v < g.numVertices (); ++v)
  {
    const auto first = g.col.begin () + g.row_ptr[v], last = g.col.begin () + g.row_ptr[v + 1];
    ASSERT_EQ (std::adjacent_find (first, last, std::greater_equal<VertexIndex> ()), last)
        << what << ": row " << v;
  }
}

} // namespace

TEST (KnnGraph, MatchesBruteForceNeighboursAndWeights)
{
  const PointMatrix p = randomPoints (400, 1);
  const int k = 7;
  KnnGraphParams params;
  params.k = k;
  const PointGraph g = buildKnnGraph (p, params);
  ASSERT_EQ (g.numVertices (), 400u);

  const auto knn = bruteKnn (p, k);
  std::set<std::pair<int, int>> expected;
  double spacing = 0.0;
  for (int i = 0; i < 400; ++i)
    for (int j : knn[i])
    {
      expected.insert ({i, j});
      expected.insert ({j, i});
      spacing += std::sqrt (dist2 (p, i, j));
    }
  spacing /= 400.0 * k;
  EXPECT_NEAR (g.spacing, spacing, 1e-6 * spacing);
  EXPECT_NEAR (g.sigma, spacing / std::sqrt (2.0), 1e-6 * spacing);

  const auto edges = edgesInCallerOrder (g);
  std::set<std::pair<int, int>> got;
  for (const auto &e : edges)
    got.insert (e.first);
  EXPECT_EQ (got, expected);
  for (const auto &e : edges)
  {
    const double w = std::exp (-dist2 (p, e.first.first, e.first.second) / (2 * g.sigma * g.sigma));
    EXPECT_NEAR (e.second, w, 1e-6);
  }
}

namespace {

/** The k-NN edge set (both directions, in the caller's rows) by brute force in single
 *  precision, with the search's own arithmetic ((dx^2 + dy^2) + dz^2), nearest by
 *  (distance, vertex): ties go to the vertex first in the graph's `order`. */
std::set<std::pair<int, int>>
bruteKnnEdgesFloat (const PointMatrix &p, int k, const std::vector<VertexIndex> &order)
{
  const int n = static_cast<int> (p.rows ());
  std::set<std::pair<int, int>> edges;
  std::vector<std::pair<float, int>> all;
  for (int v = 0; v < n; ++v)
  {
    const int i = static_cast<int> (order[v]);
    all.clear ();
    for (int w = 0; w < n; ++w)
      if (w != v)
      {
        const int j = static_cast<int> (order[w]);
        const float dx = p (i, 0) - p (j, 0), dy = p (i, 1) - p (j, 1), dz = p (i, 2) - p (j, 2);
        all.emplace_back (dx * dx + dy * dy + dz * dz, w);
      }
    std::partial_sort (all.begin (), all.begin () + k, all.end ());
    for (int m = 0; m < k; ++m)
    {
      const int j = static_cast<int> (order[all[m].second]);
      edges.insert ({i, j});
      edges.insert ({j, i});
    }
  }
  return edges;
}

} // namespace

TEST (GaussianWeight, IsTheKernelWithItsLimits)
{
  for (const double sigma : {1e-3, 1.0, 250.0})
    for (double t = 0.0; t <= 86.0; t += 0.37)  // t = d2 / (2 sigma^2)
    {
      const double d2 = 2.0 * sigma * sigma * t;
      const double expected = std::exp (-t);
      // Within a few ulps, plus the single-precision rounding of the exponent t.
      EXPECT_NEAR (gaussianWeight (d2, sigma), expected, (3e-7 + 1.2e-7 * t) * expected)
          << sigma << " " << t;
    }
  // Coincident points weigh 1 for any sigma; sigma 0 is the kernel's limit.
  EXPECT_EQ (gaussianWeight (0.0, 0.5), 1.0f);
  EXPECT_EQ (gaussianWeight (0.0, 0.0), 1.0f);
  EXPECT_EQ (gaussianWeight (1e-30, 0.0), 0.0f);
  // Weights that single precision could only hold as subnormals are 0, never negative.
  EXPECT_EQ (gaussianWeight (2.0 * 90.0, 1.0), 0.0f);
  EXPECT_EQ (gaussianWeight (1e30, 1.0), 0.0f);
  EXPECT_GT (gaussianWeight (2.0 * 86.0, 1.0), 0.0f);
}

TEST (KnnGraph, MatchesBruteForceWithOutliersFarPointsAndUnevenDensity)
{
  // The search settles most points on a grid of cells and the rest in a k-d tree: each
  // cloud here sends many points down the second way. Uniform outliers around a noisy
  // sphere (alone in their cells); two points a million units away (they stretch the
  // grid until the sphere fills a handful of crowded cells); a density that varies by
  // twelve orders of magnitude (no one cell size suits it); a line and a plane (cells
  // that hold the surface along one or two axes only); a lattice and a cloud of copies
  // (exact ties: the lower index wins, in the grid and the tree alike).
  std::mt19937 rng (11);
  std::normal_distribution<float> g (0.0f, 1.0f);
  std::uniform_real_distribution<float> u (-1.0f, 1.0f);
  const int n = 2500;
  const auto onSphere = [&] () {
    const Eigen::Vector3f s = Eigen::Vector3f (g (rng), g (rng), g (rng)).normalized ();
    return Eigen::Vector3f (s + 0.01f * Eigen::Vector3f (g (rng), g (rng), g (rng)));
  };
  std::vector<std::pair<const char *, PointMatrix>> clouds;
  PointMatrix outliers (n, 3), far (n, 3), uneven (n, 3), line (n, 3), plane (n, 3);
  for (int i = 0; i < n; ++i)
  {
    const Eigen::Vector3f box (1.2f * u (rng), 1.2f * u (rng), 1.2f * u (rng));
    outliers.row (i) = (i % 20 == 0 ? box : onSphere ()).transpose ();
    far.row (i) = onSphere ().transpose ();
    const float radius = std::pow (10.0f, 6.0f * u (rng));
    uneven.row (i) = (radius * onSphere ()).transpose ();
    line.row (i) << 5.0f * u (rng), 0.001f * u (rng), 0.0f;
    plane.row (i) << u (rng), u (rng), 0.0f;
  }
  PointMatrix lattice (n, 3), copies (n, 3);
  for (int i = 0; i < n; ++i)
  {
    lattice.row (i) << float (i % 50), float (i / 50), 0.0f;
    copies.row (i) = outliers.row (i % (n / 5));
  }
  lattice.row (0) << 1e6f, 0.0f, 0.0f;  // and one far point: it goes to the tree
  far.row (0) << 1e6f, 1e6f, -1e6f;
  far.row (1) << -1e6f, 3.0f, 2.0f;
  clouds = {{"outliers", outliers}, {"far points", far}, {"uneven density", uneven},
            {"line", line}, {"plane", plane}, {"lattice", lattice}, {"copies", copies}};
  // k = 40: rows longer than the symmetrisation scans (it sorts and bisects them).
  for (const int k : {1, 10, 25, 40})
    for (const auto &cloud : clouds)
    {
      KnnGraphParams params;
      params.k = k;
      params.num_threads = 1;
      const PointGraph graph = buildKnnGraph (cloud.second, params);
      std::set<std::pair<int, int>> got;
      for (const auto &e : edgesInCallerOrder (graph))
        got.insert (e.first);
      // The k-NN links, but for those whose weight underflows to 0 (the far points'):
      // the graph leaves them out.
      std::set<std::pair<int, int>> expected;
      for (const auto &e : bruteKnnEdgesFloat (cloud.second, k, graph.order))
        if (gaussianWeight (dist2 (cloud.second, e.first, e.second), graph.sigma) > 0.0f)
          expected.insert (e);
      EXPECT_EQ (got, expected) << cloud.first << ", k = " << k;
      EXPECT_EQ (std::count (graph.weight.begin (), graph.weight.end (), 0.0f), 0)
          << cloud.first << ", k = " << k;
      expectRowsSortedWithoutRepeats (graph,
                                      cloud.first + std::string (", k = ") + std::to_string (k));
      params.num_threads = 3;
      expectSameGraph (graph, buildKnnGraph (cloud.second, params));
    }
}

// ---- Spatio-temporal graph ------------------------------------------------------------

namespace {

/** Rows [offset, offset + frame.rows ()) of the concatenation hold `frame`. */
PointMatrix
concatenate (const std::vector<PointMatrix> &frames)
{
  Eigen::Index n = 0;
  for (const auto &f : frames)
    n += f.rows ();
  PointMatrix all (n, 3);
  Eigen::Index at = 0;
  for (const auto &f : frames)
  {
    if (f.rows ())
      all.middleRows (at, f.rows ()) = f;
    at += f.rows ();
  }
  return all;
}

} // namespace

TEST (SpatioTemporalGraph, MatchesBruteForceNeighboursAndWeights)
{
  // Frames of different sizes, one empty: each point links to its k1 nearest in its own
  // frame and its k2 nearest in each frame within the window, symmetrised.
  const std::vector<PointMatrix> frames = {randomPoints (60, 11), randomPoints (45, 12),
                                           PointMatrix (0, 3), randomPoints (70, 13),
                                           randomPoints (3, 14)};
  SpatioTemporalGraphParams params;
  params.k_spatial = 5;
  params.k_temporal = 2;
  params.window = 1;
  const PointGraph g = buildSpatioTemporalGraph (frames, params);
  const PointMatrix all = concatenate (frames);
  ASSERT_EQ (g.numVertices (), std::size_t (all.rows ()));

  std::vector<int> offset = {0};
  for (const auto &f : frames)
    offset.push_back (offset.back () + int (f.rows ()));
  std::set<std::pair<int, int>> expected;
  double spacing = 0.0;
  int with_neighbours = 0;
  for (std::size_t f = 0; f < frames.size (); ++f)
  {
    const int m = int (frames[f].rows ());
    if (m == 0)
      continue;
    const int k1 = std::min (params.k_spatial, m - 1);
    const auto knn = bruteKnn (frames[f], k1);
    for (int i = 0; i < m; ++i)
    {
      double sum = 0.0;
      for (int j : knn[i])
      {
        expected.insert ({offset[f] + i, offset[f] + j});
        expected.insert ({offset[f] + j, offset[f] + i});
        sum += std::sqrt (dist2 (frames[f], i, j));
      }
      if (k1 > 0)
      {
        spacing += sum / k1;
        ++with_neighbours;
      }
      // Temporal: the k2 nearest in frames f - 1 and f + 1 (none in the empty one).
      for (int h : {int (f) - 1, int (f) + 1})
      {
        if (h < 0 || h >= int (frames.size ()) || frames[h].rows () == 0)
          continue;
        std::vector<std::pair<double, int>> cand;
        for (int j = 0; j < int (frames[h].rows ()); ++j)
          cand.emplace_back ((frames[f].row (i).cast<double> () - frames[h].row (j).cast<double> ())
                                 .squaredNorm (),
                             j);
        std::sort (cand.begin (), cand.end ());
        for (int t = 0; t < std::min (params.k_temporal, int (cand.size ())); ++t)
        {
          expected.insert ({offset[f] + i, offset[h] + cand[t].second});
          expected.insert ({offset[h] + cand[t].second, offset[f] + i});
        }
      }
    }
  }
  spacing /= with_neighbours;
  EXPECT_NEAR (g.spacing, spacing, 1e-6 * spacing);
  EXPECT_NEAR (g.sigma, spacing / std::sqrt (2.0), 1e-6 * spacing);
  const auto edges = edgesInCallerOrder (g);
  std::set<std::pair<int, int>> got;
  for (const auto &e : edges)
    got.insert (e.first);
  EXPECT_EQ (got, expected);
  for (const auto &e : edges)
    EXPECT_NEAR (e.second,
                 std::exp (-dist2 (all, e.first.first, e.first.second) / (2 * g.sigma * g.sigma)),
                 1e-6);
  // Frames 1 and 3 are two apart (the empty frame 2 between them): never linked.
  for (const auto &e : edges)
  {
    const int a = e.first.first, b = e.first.second;
    EXPECT_FALSE (a >= offset[1] && a < offset[2] && b >= offset[3] && b < offset[4]);
  }
}

TEST (SpatioTemporalGraph, OneFrameIsTheStaticGraph)
{
  const PointMatrix p = randomPoints (500, 21);
  SpatioTemporalGraphParams params;
  params.k_spatial = 8;
  KnnGraphParams knn;
  knn.k = 8;
  expectSameGraph (buildSpatioTemporalGraph ({p}, params), buildKnnGraph (p, knn));
}

TEST (SpatioTemporalGraph, NoTemporalNeighboursIsEachFrameOnItsOwn)
{
  // k2 = 0 with an explicit theta: the edges and weights of each frame's static graph.
  const std::vector<PointMatrix> frames = {randomPoints (200, 31), randomPoints (150, 32),
                                           randomPoints (180, 33)};
  SpatioTemporalGraphParams params;
  params.k_temporal = 0;
  params.sigma = 0.05;
  const auto edges = edgesInCallerOrder (buildSpatioTemporalGraph (frames, params));
  std::map<std::pair<int, int>, float> expected;
  int offset = 0;
  for (const auto &f : frames)
  {
    KnnGraphParams knn;
    knn.sigma = params.sigma;
    for (const auto &e : edgesInCallerOrder (buildKnnGraph (f, knn)))
      expected[{e.first.first + offset, e.first.second + offset}] = e.second;
    offset += int (f.rows ());
  }
  EXPECT_EQ (edges, expected);
}

TEST (SpatioTemporalGraph, WiderWindowLinksFartherFramesAndThreadsDoNotMatter)
{
  std::vector<PointMatrix> frames;
  for (int t = 0; t < 5; ++t)
    frames.push_back (randomPoints (3000, 40 + t));
  SpatioTemporalGraphParams params;
  params.window = 2;
  params.num_threads = 1;
  const PointGraph one = buildSpatioTemporalGraph (frames, params);
  params.num_threads = 2;
  expectSameGraph (one, buildSpatioTemporalGraph (frames, params));
  params.num_threads = 3;
  expectSameGraph (one, buildSpatioTemporalGraph (frames, params));
  // Frame 0 reaches frame 2 (window 2) but not frame 3.
  bool two_apart = false;
  for (const auto &e : edgesInCallerOrder (one))
  {
    const int fa = e.first.first / 3000, fb = e.first.second / 3000;
    EXPECT_LE (std::abs (fa - fb), 2);
    two_apart = two_apart || std::abs (fa - fb) == 2;
  }
  EXPECT_TRUE (two_apart);
}

TEST (SpatioTemporalGraph, DegenerateSequencesAndInvalidParameters)
{
  EXPECT_EQ (buildSpatioTemporalGraph ({}).numVertices (), 0u);
  EXPECT_EQ (buildSpatioTemporalGraph ({PointMatrix (0, 3), PointMatrix (0, 3)}).numEdges (), 0u);
  // One point per frame: linked through time only, with theta from those links.
  PointMatrix a (1, 3), b (1, 3);
  a << 0, 0, 0;
  b << 0.1f, 0, 0;
  const PointGraph pair = buildSpatioTemporalGraph ({a, b});
  EXPECT_EQ (pair.numEdges (), 1u);
  EXPECT_NEAR (pair.spacing, 0.1, 1e-6);
  EXPECT_GT (pair.weight[0], 0.0f);
  // Identical frames (a static scene): every point also links to its copy.
  const PointMatrix p = randomPoints (100, 51);
  const auto edges = edgesInCallerOrder (buildSpatioTemporalGraph ({p, p}));
  for (int i = 0; i < 100; ++i)
  {
    ASSERT_EQ (edges.count ({i, i + 100}), 1u);
    EXPECT_EQ (edges.at ({i, i + 100}), 1.0f);
  }
  PointMatrix bad = randomPoints (10, 52);
  bad (3, 1) = std::numeric_limits<float>::quiet_NaN ();
  SpatioTemporalGraphParams params;
  EXPECT_THROW (buildSpatioTemporalGraph ({p, bad}), std::invalid_argument);
  params.k_spatial = 0;
  EXPECT_THROW (buildSpatioTemporalGraph ({p}, params), std::invalid_argument);
  params = {};
  params.k_temporal = -1;
  EXPECT_THROW (buildSpatioTemporalGraph ({p}, params), std::invalid_argument);
  params = {};
  params.window = -1;
  EXPECT_THROW (buildSpatioTemporalGraph ({p}, params), std::invalid_argument);
  params = {};
  params.sigma = std::numeric_limits<double>::infinity ();
  EXPECT_THROW (buildSpatioTemporalGraph ({p}, params), std::invalid_argument);
}

TEST (KnnGraph, AnIsolatedFarPointSetsNoScaleAndKeepsNoWeightlessLink)
{
  // A plane spaced 0.01 apart and a point 1,000 units away: the far point's links weigh
  // 0 and are left out, and its distances do not enter the spacing (with them, a plain
  // mean made theta 75 times the plane's).
  std::mt19937 rng (9);
  std::uniform_real_distribution<float> jitter (-0.001f, 0.001f);  // no ties
  PointMatrix plane (900, 3), both (901, 3);
  for (int i = 0; i < 900; ++i)
    plane.row (i) << 0.01f * float (i % 30) + jitter (rng), 0.01f * float (i / 30) + jitter (rng),
        jitter (rng);
  both.topRows (900) = plane;
  both.row (900) << 1000.0f, 0.1f, 0.0f;
  const PointGraph alone = buildKnnGraph (plane), g = buildKnnGraph (both);
  EXPECT_NEAR (g.spacing, alone.spacing, 1e-12 * alone.spacing);
  EXPECT_NEAR (g.sigma, alone.sigma, 1e-12 * alone.sigma);
  EXPECT_EQ (std::count (g.weight.begin (), g.weight.end (), 0.0f), 0);
  const auto with = edgesInCallerOrder (g), without = edgesInCallerOrder (alone);
  ASSERT_EQ (with.size (), without.size ());  // the far point: no link
  for (auto a = with.begin (), b = without.begin (); a != with.end (); ++a, ++b)
  {
    ASSERT_EQ (a->first, b->first);
    EXPECT_NEAR (a->second, b->second, 1e-6);
  }
  // The same in a sequence's graph.
  SpatioTemporalGraphParams sequence;
  const PointGraph frames = buildSpatioTemporalGraph ({both, both}, sequence);
  EXPECT_NEAR (frames.spacing, alone.spacing, 1e-12 * alone.spacing);
  EXPECT_EQ (std::count (frames.weight.begin (), frames.weight.end (), 0.0f), 0);
}

TEST (KnnGraph, IsSymmetricSortedAndLoopFree)
{
  const PointGraph g = buildKnnGraph (randomPoints (1000, 2));
  const auto edges = edgesInCallerOrder (g);
  for (const auto &e : edges)
  {
    EXPECT_NE (e.first.first, e.first.second);
    const auto back = edges.find ({e.first.second, e.first.first});
    ASSERT_NE (back, edges.end ());
    EXPECT_EQ (back->second, e.second);  // bit for bit
  }
  expectRowsSortedWithoutRepeats (g, "k = 10");
  // Every vertex has at least its k neighbours.
  for (std::size_t v = 0; v < g.numVertices (); ++v)
    EXPECT_GE (g.row_ptr[v + 1] - g.row_ptr[v], 10u);
}

TEST (KnnGraph, OrderIsAPermutation)
{
  const PointGraph g = buildKnnGraph (randomPoints (3000, 3));
  std::vector<VertexIndex> sorted = g.order;
  std::sort (sorted.begin (), sorted.end ());
  for (std::size_t i = 0; i < sorted.size (); ++i)
    ASSERT_EQ (sorted[i], i);
}

TEST (KnnGraph, ResultDoesNotDependOnThreadCount)
{
  const PointMatrix p = randomPoints (20000, 4);
  KnnGraphParams one, two, five;
  one.num_threads = 1;
  two.num_threads = 2;
  five.num_threads = 5;
  const PointGraph a = buildKnnGraph (p, one);
  expectSameGraph (a, buildKnnGraph (p, two));
  expectSameGraph (a, buildKnnGraph (p, five));

  RadiusGraphParams r1, r3;
  r1.num_threads = 1;
  r3.num_threads = 3;
  expectSameGraph (buildRadiusGraph (p, r1), buildRadiusGraph (p, r3));
}

TEST (KnnGraph, UnitInvariantDefaults)
{
  const PointMatrix metres = randomPoints (2000, 5);
  const PointMatrix millimetres = metres * 1000.0f;
  const PointGraph a = buildKnnGraph (metres), b = buildKnnGraph (millimetres);
  EXPECT_EQ (a.order, b.order);
  EXPECT_EQ (a.col, b.col);
  EXPECT_NEAR (b.sigma, 1000.0 * a.sigma, 1e-4 * b.sigma);
  for (std::size_t e = 0; e < a.weight.size (); ++e)
    ASSERT_NEAR (a.weight[e], b.weight[e], 1e-5);
}

TEST (KnnGraph, ExplicitSigmaIsUsed)
{
  KnnGraphParams params;
  params.sigma = 0.25;
  const PointMatrix p = randomPoints (300, 6);
  const PointGraph g = buildKnnGraph (p, params);
  EXPECT_EQ (g.sigma, 0.25);
  const auto edges = edgesInCallerOrder (g);
  for (const auto &e : edges)
    EXPECT_NEAR (e.second, std::exp (-dist2 (p, e.first.first, e.first.second) / (2 * 0.0625)), 1e-6);
}

TEST (KnnGraph, KAtLeastNGivesTheCompleteGraph)
{
  KnnGraphParams params;
  params.k = 10;
  const PointGraph g = buildKnnGraph (randomPoints (5, 7), params);
  ASSERT_EQ (g.numVertices (), 5u);
  EXPECT_EQ (g.numEntries (), 20u);
  EXPECT_EQ (g.numEdges (), 10u);
}

TEST (KnnGraph, EmptyAndSinglePoint)
{
  const PointGraph empty = buildKnnGraph (PointMatrix (0, 3));
  EXPECT_EQ (empty.numVertices (), 0u);
  EXPECT_EQ (empty.row_ptr.size (), 1u);
  const PointGraph one = buildKnnGraph (randomPoints (1, 8));
  EXPECT_EQ (one.numVertices (), 1u);
  EXPECT_EQ (one.numEntries (), 0u);
  EXPECT_TRUE (weightedDegree (one).at (0) == 0.0);
}

TEST (KnnGraph, DuplicatePointsNeverLinkToThemselves)
{
  PointMatrix p = randomPoints (50, 9);
  PointMatrix dup (150, 3);
  dup << p, p, p;  // every point three times
  const PointGraph g = buildKnnGraph (dup);
  for (std::size_t v = 0; v < g.numVertices (); ++v)
    for (auto e = g.row_ptr[v]; e < g.row_ptr[v + 1]; ++e)
    {
      ASSERT_NE (g.col[e], v);
      ASSERT_TRUE (std::isfinite (g.weight[e]));
    }
  // Each point sees its two copies at distance zero, with weight one.
  const auto edges = edgesInCallerOrder (g);
  EXPECT_EQ (edges.at ({0, 50}), 1.0f);
  EXPECT_EQ (edges.at ({0, 100}), 1.0f);
}

TEST (KnnGraph, AllPointsIdentical)
{
  const PointMatrix p = PointMatrix::Constant (30, 3, 2.5f);
  const PointGraph g = buildKnnGraph (p);
  EXPECT_EQ (g.spacing, 0.0);
  for (float w : g.weight)
    EXPECT_EQ (w, 1.0f);
}

TEST (KnnGraph, RejectsInvalidInput)
{
  const PointMatrix p = randomPoints (20, 10);
  KnnGraphParams bad_k;
  bad_k.k = 0;
  EXPECT_THROW (buildKnnGraph (p, bad_k), std::invalid_argument);
  KnnGraphParams bad_sigma;
  bad_sigma.sigma = -1.0;
  EXPECT_THROW (buildKnnGraph (p, bad_sigma), std::invalid_argument);
  bad_sigma.sigma = std::nan ("");
  EXPECT_THROW (buildKnnGraph (p, bad_sigma), std::invalid_argument);
  KnnGraphParams bad_threads;
  bad_threads.num_threads = -2;
  EXPECT_THROW (buildKnnGraph (p, bad_threads), std::invalid_argument);
  PointMatrix nan_point = p;
  nan_point (3, 1) = std::numeric_limits<float>::infinity ();
  EXPECT_THROW (buildKnnGraph (nan_point), std::invalid_argument);
  RadiusGraphParams bad_radius;
  bad_radius.radius = -0.5;
  EXPECT_THROW (buildRadiusGraph (p, bad_radius), std::invalid_argument);
  RadiusGraphParams bad_factor;
  bad_factor.radius_factor = 0.0;
  EXPECT_THROW (buildRadiusGraph (p, bad_factor), std::invalid_argument);
  RadiusGraphParams bad_sigma_factor;
  bad_sigma_factor.sigma_factor = -1.0;
  EXPECT_THROW (radiusGraphDegrees (p, bad_sigma_factor), std::invalid_argument);
}

TEST (RadiusGraph, MatchesBruteForce)
{
  const PointMatrix p = randomPoints (500, 11);
  RadiusGraphParams params;
  params.radius = 0.3;
  params.sigma = 0.1;
  double used = 0.0;
  const PointGraph g = buildRadiusGraph (p, params, &used);
  EXPECT_EQ (used, 0.3);
  std::set<std::pair<int, int>> expected;
  for (int i = 0; i < 500; ++i)
    for (int j = 0; j < 500; ++j)
      if (i != j && dist2 (p, i, j) < 0.09)
        expected.insert ({i, j});
  const auto edges = edgesInCallerOrder (g);
  std::set<std::pair<int, int>> got;
  for (const auto &e : edges)
  {
    got.insert (e.first);
    EXPECT_NEAR (e.second, std::exp (-dist2 (p, e.first.first, e.first.second) / 0.02), 1e-6);
  }
  EXPECT_EQ (got, expected);
  expectRowsSortedWithoutRepeats (g, "radius 0.3");
}

TEST (RadiusGraph, DefaultRadiusFollowsTheMedianSpacing)
{
  const PointMatrix p = randomPoints (2000, 12);
  double used = 0.0;
  const PointGraph g = buildRadiusGraph (p, {}, &used);
  // Median over points of the mean 10-NN distance, by brute force.
  const auto knn = bruteKnn (p, 10);
  std::vector<double> mean;
  for (int i = 0; i < 2000; ++i)
  {
    double s = 0.0;
    for (int j : knn[i])
      s += std::sqrt (dist2 (p, i, j));
    mean.push_back (s / 10.0);
  }
  std::nth_element (mean.begin (), mean.begin () + 1000, mean.end ());
  EXPECT_NEAR (g.spacing, mean[1000], 1e-6);
  EXPECT_NEAR (used, 2.0 * mean[1000], 1e-6);
  EXPECT_NEAR (g.sigma, mean[1000] / std::sqrt (2.0), 1e-6);
  RadiusGraphParams scaled;
  scaled.radius_factor = 3.0;
  scaled.sigma_factor = 1.0;
  double used_scaled = 0.0;
  const PointGraph h = buildRadiusGraph (p, scaled, &used_scaled);
  EXPECT_NEAR (used_scaled, 3.0 * mean[1000], 1e-6);
  EXPECT_NEAR (h.sigma, mean[1000], 1e-6);
  // Far outliers do not move a median: add 5% of points 100 units away.
  PointMatrix with_outliers (2100, 3);
  with_outliers << p, randomPoints (100, 13) .array () + 100.0f;
  double used_outliers = 0.0;
  buildRadiusGraph (with_outliers, {}, &used_outliers);
  EXPECT_NEAR (used_outliers, used, 0.1 * used);
}

TEST (RadiusGraph, DegreesWithoutTheGraphMatchTheGraphsDegrees)
{
  const PointMatrix p = randomPoints (5000, 17);
  RadiusGraphParams params;
  params.num_threads = 1;
  double radius = 0.0;
  const PointGraph g = buildRadiusGraph (p, params, &radius);
  const std::vector<double> by_vertex = weightedDegree (g);
  const RadiusDegrees d = radiusGraphDegrees (p, params);
  EXPECT_EQ (d.radius, radius);
  EXPECT_EQ (d.sigma, g.sigma);
  EXPECT_EQ (d.spacing, g.spacing);
  ASSERT_EQ (d.degree.size (), 5000u);
  for (std::size_t v = 0; v < 5000; ++v)
    ASSERT_NEAR (d.degree[g.order[v]], by_vertex[v], 1e-9 * (1.0 + by_vertex[v]));
  params.num_threads = 2;
  EXPECT_EQ (radiusGraphDegrees (p, params).degree, d.degree);
}

namespace {

/** n points uniform on the square [0, 1]^2 at z = `height`, with Gaussian noise of
 *  standard deviation `noise` along z. */
PointMatrix
noisySquare (int n, float noise, std::uint64_t seed, float height = 0.0f)
{
  std::mt19937_64 rng (seed);
  std::uniform_real_distribution<float> u (0.0f, 1.0f);
  std::normal_distribution<float> g (0.0f, 1.0f);
  PointMatrix p (n, 3);
  for (int i = 0; i < n; ++i)
    p.row (i) << u (rng), u (rng), height + noise * g (rng);
  return p;
}

/** n points uniform on the surface of the cube [-1, 1]^3 (sharp edges and corners). */
PointMatrix
cubeSurface (int n, std::uint64_t seed)
{
  std::mt19937_64 rng (seed);
  std::uniform_real_distribution<float> u (-1.0f, 1.0f);
  PointMatrix p (n, 3);
  for (int i = 0; i < n; ++i)
  {
    const int face = i % 6;
    p.row (i) << u (rng), u (rng), u (rng);
    p (i, face / 2) = face % 2 ? 1.0f : -1.0f;
  }
  return p;
}

} // namespace

TEST (RadiusGraph, NormalResidualFlagsPointsOffTheSurfaceOnly)
{
  const float noise = 0.002f;
  PointMatrix p (4000 + 6, 3);
  p.topRows (4000) = noisySquare (4000, noise, 31);
  // Probes well apart, at 1, 2 and 6, 8, 10, 11 noise levels above the plane: all
  // well within epsilon of it, where their degree is an inlier's.
  const float heights[6] = {1, 2, 6, 8, 10, 11};
  for (int m = 0; m < 6; ++m)
    p.row (4000 + m) << 0.15f + 0.14f * m, 0.5f, heights[m] * noise;
  RadiusGraphParams params;
  params.residual_multiplier = 4.0;
  const RadiusDegrees d = radiusGraphDegrees (p, params);
  ASSERT_EQ (d.off_surface.size (), p.rows ());
  ASSERT_LT (heights[5] * noise, 0.6 * d.radius);
  EXPECT_FALSE (d.off_surface[4000]);
  EXPECT_FALSE (d.off_surface[4001]);
  for (int m = 2; m < 6; ++m)
    EXPECT_TRUE (d.off_surface[4000 + m]) << heights[m] << " noise levels off";
  // The noise scale is the noise: residuals are the noise less its mean over a neighbourhood.
  EXPECT_NEAR (d.residual_scale, noise, 0.2 * noise);
  std::size_t flagged = 0;
  for (int i = 0; i < 4000; ++i)
    flagged += d.off_surface[i];
  EXPECT_LE (flagged, 4u);  // a Gaussian's tail beyond about 4 sigma
  // The flags do not depend on the number of threads.
  params.num_threads = 1;
  EXPECT_EQ (radiusGraphDegrees (p, params).off_surface, d.off_surface);
  // Nor do the degrees on the test.
  params.residual_multiplier = 0.0;
  EXPECT_EQ (radiusGraphDegrees (p, params).degree, d.degree);
}

TEST (RadiusGraph, AutomaticDegreeThresholdIsARatioOfTheFirstQuartile)
{
  const std::vector<double> degrees = {4, 1, 3, 2, 8, 6, 7, 5};  // first quartile: 3
  EXPECT_DOUBLE_EQ (automaticDegreeThreshold (degrees, 0.5).threshold, 1.5);
  EXPECT_EQ (automaticDegreeThreshold (degrees, 0.5).without_neighbour, 0u);
  // More than a quarter without a neighbour: the others' quartile (of 4, 5, 6, 7, 8: 5).
  const std::vector<double> isolated = {0, 0, 0, 4, 8, 6, 7, 5};
  EXPECT_DOUBLE_EQ (automaticDegreeThreshold (isolated, 0.5).threshold, 2.5);
  EXPECT_EQ (automaticDegreeThreshold (isolated, 0.5).without_neighbour, 3u);
  EXPECT_DOUBLE_EQ (automaticDegreeThreshold (isolated, 0.0).threshold, 0.0);
  EXPECT_DOUBLE_EQ (automaticDegreeThreshold ({}, 0.5).threshold, 0.0);
  // None with a neighbour: nothing to derive the threshold from, and all of them counted.
  EXPECT_DOUBLE_EQ (automaticDegreeThreshold ({0, 0}, 0.5).threshold, 0.0);
  EXPECT_EQ (automaticDegreeThreshold ({0, 0, 0}, 0.5).without_neighbour, 3u);
  EXPECT_THROW (automaticDegreeThreshold (degrees, -1.0), std::invalid_argument);
  EXPECT_THROW (automaticDegreeThreshold (degrees, std::nan ("")), std::invalid_argument);
  RadiusGraphParams bad;
  bad.sparse_surface_ratio = -0.2;
  EXPECT_THROW (radiusGraphDegrees (noisySquare (100, 0.0f, 1), bad), std::invalid_argument);
}

TEST (RadiusGraph, SparseSurfaceContinuesARecedingFloorOnly)
{
  using pcl_graph_denoise::testing::FloorPart;
  std::vector<FloorPart> parts;
  const auto cloud = pcl_graph_denoise::testing::recedingFloor (300, 5, parts);
  PointMatrix p = synthetic::toMatrix (cloud);
  // A patch as sparse as the far floor but apart from it (5 units above its near end),
  // whose density does not continue the floor's: not reached. And a ring of 200 points
  // 0.63 apart, 20 units around the floor (a spinning scanner's far ring): out of reach
  // too, but a line as dense as itself, so it starts a growth of its own.
  const Eigen::Index patch = p.rows (), ring = patch + 100;
  p.conservativeResize (p.rows () + 300, 3);
  for (int i = 0; i < 100; ++i)
    p.row (patch + i) << 0.1f * float (i % 10), 0.1f * float (i / 10), 5.0f;
  for (int i = 0; i < 200; ++i)
  {
    const float angle = 0.0314159f * float (i);
    p.row (ring + i) << 5.0f + 20.0f * std::cos (angle), 20.0f * std::sin (angle), 0.0f;
  }
  RadiusGraphParams params;
  params.sparse_surface_ratio = 0.2;
  const RadiusDegrees d = radiusGraphDegrees (p, params);
  ASSERT_EQ (d.sparse_surface.size (), std::size_t (p.rows ()));
  const double threshold = automaticDegreeThreshold (d.degree, 0.2).threshold;
  std::size_t far = 0, far_low = 0, far_kept = 0, outliers_flagged = 0, near_flagged = 0;
  for (Eigen::Index i = 0; i < patch; ++i)
  {
    const bool low = d.degree[i] < threshold;
    switch (parts[i])
    {
    case FloorPart::FAR:
      ++far;
      far_low += low;
      far_kept += !low || d.sparse_surface[i];
      break;
    case FloorPart::OUTLIER:
      outliers_flagged += d.sparse_surface[i];
      break;
    case FloorPart::NEAR:
      near_flagged += d.sparse_surface[i] && !low;
      break;
    }
  }
  // The degree test alone loses most of the far floor; the growth keeps nearly all of it.
  EXPECT_GT (far_low, far / 2) << far;
  EXPECT_GE (far_kept, far - far / 50) << far_low;
  EXPECT_EQ (outliers_flagged, 0u);
  EXPECT_EQ (near_flagged, 0u);  // only points below the threshold are flagged
  for (Eigen::Index i = patch; i < ring; ++i)
    EXPECT_FALSE (d.sparse_surface[i]) << "patch point " << i - patch;
  for (Eigen::Index i = ring; i < p.rows (); ++i)
    ASSERT_LT (d.degree[i], threshold);
  for (Eigen::Index i = ring; i < p.rows (); ++i)
    EXPECT_TRUE (d.sparse_surface[i]) << "ring point " << i - ring;
  // The flags do not depend on the number of threads, nor on the row order.
  params.num_threads = 1;
  EXPECT_EQ (radiusGraphDegrees (p, params).sparse_surface, d.sparse_surface);
  PointMatrix reversed = p.colwise ().reverse ();
  const RadiusDegrees r = radiusGraphDegrees (reversed, params);
  for (Eigen::Index i = 0; i < p.rows (); ++i)
    ASSERT_EQ (r.sparse_surface[p.rows () - 1 - i], d.sparse_surface[i]) << i;
  // Each point sampled twice (a scan that repeats itself): the copies count once, and
  // every copy gets its position's flag.
  PointMatrix doubled (2 * p.rows (), 3);
  doubled << p, p;
  const RadiusDegrees twice = radiusGraphDegrees (doubled, params);
  const double twice_threshold = automaticDegreeThreshold (twice.degree, 0.2).threshold;
  std::size_t twice_far_kept = 0;
  for (Eigen::Index i = 0; i < p.rows (); ++i)
  {
    ASSERT_EQ (twice.sparse_surface[i], twice.sparse_surface[p.rows () + i]) << i;
    if (i < patch && parts[i] == FloorPart::FAR)
      twice_far_kept += twice.degree[i] >= twice_threshold || twice.sparse_surface[i];
    if ((i >= patch && i < ring) || (i < patch && parts[i] == FloorPart::OUTLIER))
      ASSERT_FALSE (twice.sparse_surface[i]) << i;
    if (i >= ring)  // (a copy's weight of 1 may lift it over the threshold alone)
      ASSERT_TRUE (twice.sparse_surface[i] || twice.degree[i] >= twice_threshold) << i;
  }
  EXPECT_GE (twice_far_kept, far - far / 50);
  // Off (the default): no flags, and the degrees are the same.
  params.sparse_surface_ratio = 0.0;
  const RadiusDegrees off = radiusGraphDegrees (p, params);
  EXPECT_TRUE (off.sparse_surface.empty ());
  EXPECT_EQ (off.degree, d.degree);
}

TEST (RadiusGraph, NormalResidualFitsTheNearestNeighboursOfACrowdedBall)
{
  // A wide epsilon on a curved surface: each ball holds about 1,500 points of a sphere,
  // and the plane through them all sags below each point by about r^2 / 4 = 0.076, which
  // sets the cloud's residual scale, so that a probe 0.15 off the sphere hides (checked:
  // with every neighbour fitted, none of the probes is flagged). The plane of the nearest
  // 256 (a cap of radius about 0.23) sags by about 0.013, and the probes stand out.
  const float noise = 0.002f;
  const auto sphere = synthetic::noisySphere (20000, 1.0, noise, 41);
  PointMatrix p (20000 + 8, 3);
  p.topRows (20000) = synthetic::toMatrix (sphere);
  for (int m = 0; m < 8; ++m)
  {
    const Eigen::Vector3f direction =
        Eigen::Vector3f (std::cos (0.8f * m), std::sin (0.8f * m), 0.3f * float (m % 3) - 0.3f).normalized ();
    p.row (20000 + m) = (1.15f * direction).transpose ();
  }
  RadiusGraphParams params;
  params.radius = 0.55;
  params.sigma = 0.2;
  params.residual_multiplier = 4.0;
  const RadiusDegrees d = radiusGraphDegrees (p, params);
  for (int m = 0; m < 8; ++m)
    EXPECT_TRUE (d.off_surface[20000 + m]) << "probe " << m;
  std::size_t flagged = 0;
  for (int i = 0; i < 20000; ++i)
    flagged += d.off_surface[i];
  EXPECT_LE (flagged, 20u);
  params.num_threads = 1;
  EXPECT_EQ (radiusGraphDegrees (p, params).off_surface, d.off_surface);
}

TEST (RadiusGraph, NormalResidualIsNotMaskedByAFewOutliersNearby)
{
  // Two outliers close to each other, 10 noise levels above the plane: each is among the
  // other's neighbours, and the refit without the neighbours off the first plane keeps
  // that from hiding it.
  const float noise = 0.002f;
  PointMatrix p (4002, 3);
  p.topRows (4000) = noisySquare (4000, noise, 32);
  p.row (4000) << 0.5f, 0.5f, 10 * noise;
  p.row (4001) << 0.51f, 0.5f, 10 * noise;
  RadiusGraphParams params;
  params.residual_multiplier = 4.0;
  const RadiusDegrees d = radiusGraphDegrees (p, params);
  EXPECT_TRUE (d.off_surface[4000]);
  EXPECT_TRUE (d.off_surface[4001]);
}

TEST (RadiusGraph, NormalResidualKeepsALayerButNotALonePoint)
{
  // A noiseless 60 x 60 grid (as a depth camera's quantised depth: flat levels) where a
  // row of three neighbouring points sits half a grid step higher (as mixed pixels along a
  // silhouette), and one point alone at that height elsewhere: each point of the row has
  // others level with it and stays; the lone point goes.
  const int side = 60;
  const float h = 1.0f / side;
  PointMatrix p (side * side, 3);
  for (int r = 0; r < side; ++r)
    for (int c = 0; c < side; ++c)
      p.row (r * side + c) << c * h, r * h, 0.0f;
  std::set<int> row;
  for (int c = 20; c < 23; ++c)
    row.insert (30 * side + c);
  for (const int i : row)
    p (i, 2) = 0.5f * h;
  const int lone = 30 * side + 45;
  p (lone, 2) = 0.5f * h;
  RadiusGraphParams params;
  params.residual_multiplier = 4.0;
  const RadiusDegrees d = radiusGraphDegrees (p, params);
  EXPECT_TRUE (d.off_surface[lone]);
  for (int i = 0; i < p.rows (); ++i)
    if (i != lone)
      EXPECT_FALSE (d.off_surface[i]) << "point " << i << (row.count (i) ? " (row)" : "");
}

TEST (RadiusGraph, NormalResidualKeepsSharpEdgesCornersAndNoiselessSurfaces)
{
  RadiusGraphParams params;
  params.residual_multiplier = 4.0;
  for (const int n : {2000, 20000})
  {
    const RadiusDegrees d = radiusGraphDegrees (cubeSurface (n, 33), params);
    EXPECT_EQ (std::count (d.off_surface.begin (), d.off_surface.end (), 1), 0) << n << " points";
  }
  // A noiseless plane far from the origin: rounding is not noise.
  const RadiusDegrees far = radiusGraphDegrees (noisySquare (3000, 0.0f, 34, 1e4f), params);
  EXPECT_EQ (std::count (far.off_surface.begin (), far.off_surface.end (), 1), 0);
  EXPECT_GT (far.residual_scale, 0.0);
}

TEST (RadiusGraph, QueryRowsAreSearchedAmongEveryPoint)
{
  // The first rows are the queries; their degrees, residual verdicts and distances are
  // the ones the whole set gives them, at the same radius and theta, and the derived
  // spacing is the queries' median.
  const PointMatrix p = noisySquare (4000, 0.01f, 36);
  const std::size_t q = 1000;
  RadiusGraphParams params;
  params.residual_multiplier = 4.0;
  params.num_threads = 2;
  const RadiusDegrees all = radiusGraphDegrees (p, params);
  params.radius = all.radius;
  params.sigma = all.sigma;
  const RadiusDegrees fixed_all = radiusGraphDegrees (p, params);
  params.query_rows = q;
  const RadiusDegrees some = radiusGraphDegrees (p, params);
  ASSERT_EQ (some.degree.size (), q);
  ASSERT_EQ (some.off_surface.size (), q);
  ASSERT_EQ (some.mean_knn_distance.size (), q);
  for (std::size_t r = 0; r < q; ++r)
  {
    ASSERT_NEAR (some.degree[r], fixed_all.degree[r], 1e-9 * (1.0 + fixed_all.degree[r])) << r;
    ASSERT_EQ (some.mean_knn_distance[r], fixed_all.mean_knn_distance[r]) << r;
  }
  std::vector<float> first (all.mean_knn_distance.begin (), all.mean_knn_distance.begin () + q);
  std::nth_element (first.begin (), first.begin () + q / 2, first.end ());
  params.radius = params.sigma = 0.0;
  EXPECT_FLOAT_EQ (static_cast<float> (radiusGraphDegrees (p, params).spacing), first[q / 2]);
  // A query among points it does not name: its degree counts them.
  const PointMatrix one = p.topRows (1);
  params.query_rows = 0;
  params.radius = all.radius;
  EXPECT_EQ (radiusGraphDegrees (one, params).degree[0], 0.0);
  params.query_rows = 1;
  EXPECT_GT (radiusGraphDegrees (p, params).degree[0], 0.0);
  params.query_rows = p.rows () + 1;
  EXPECT_THROW (radiusGraphDegrees (p, params), std::invalid_argument);
  params.query_rows = 2;
  EXPECT_THROW (radiusGraphDegrees (one, params), std::invalid_argument);
}

TEST (DistinctPoints, CopiesAreMergedInTheOrderOfTheirFirstRows)
{
  PointMatrix p (6, 3);
  p << 1, 2, 3,  //
      0, 0, 0,   //
      1, 2, 3,   // a copy of row 0
      -0.0f, 0, 0,  // -0 == 0: a copy of row 1
      1, 2, 3.5f,   //
      1, 2, 3;      // row 0 again
  const DistinctPoints d = distinctPoints (p);
  EXPECT_EQ (d.copies, 3u);
  ASSERT_EQ (d.points.rows (), 3);
  EXPECT_EQ (d.of_row, (std::vector<VertexIndex>{0, 1, 0, 1, 2, 0}));
  for (Eigen::Index r = 0; r < p.rows (); ++r)
    EXPECT_TRUE ((d.points.row (d.of_row[static_cast<std::size_t> (r)]) - p.row (r)).isZero ()) << r;
  // Without copies: nothing to merge, the input is the answer.
  const PointMatrix q = randomPoints (1000, 3);
  const DistinctPoints none = distinctPoints (q);
  EXPECT_EQ (none.copies, 0u);
  EXPECT_EQ (none.points.rows (), 0);
  for (std::size_t r = 0; r < 1000; ++r)
    ASSERT_EQ (none.of_row[r], r);
  EXPECT_TRUE (distinctPoints (PointMatrix (0, 3)).of_row.empty ());
}

TEST (RadiusGraph, HeavilyDuplicatedPointsGiveTheDistinctPositionsSpacing)
{
  // Every point 12 times: the median mean distance to the 10 nearest is 0; the spacing
  // (and the radius) is then the distinct positions'.
  const PointMatrix p = noisySquare (500, 0.01f, 37);
  PointMatrix copies (12 * p.rows (), 3);
  for (int c = 0; c < 12; ++c)
    copies.middleRows (c * p.rows (), p.rows ()) = p;
  const RadiusDegrees alone = radiusGraphDegrees (p), repeated = radiusGraphDegrees (copies);
  EXPECT_GT (alone.spacing, 0.0);
  EXPECT_DOUBLE_EQ (repeated.spacing, alone.spacing);
  EXPECT_DOUBLE_EQ (repeated.radius, alone.radius);
  // Each copy counts as a neighbour of weight 1 (the degree is a density).
  EXPECT_NEAR (repeated.degree[0], 12.0 * alone.degree[0] + 11.0, 1e-9 * repeated.degree[0]);
}

TEST (RadiusGraph, NormalResidualOffByDefaultAndValidated)
{
  const PointMatrix p = noisySquare (500, 0.01f, 35);
  const RadiusDegrees d = radiusGraphDegrees (p);
  EXPECT_TRUE (d.off_surface.empty ());
  EXPECT_EQ (d.residual_scale, 0.0);
  for (const double bad : {-1.0, std::numeric_limits<double>::quiet_NaN (),
                           std::numeric_limits<double>::infinity ()})
  {
    RadiusGraphParams params;
    params.residual_multiplier = bad;
    EXPECT_THROW (radiusGraphDegrees (p, params), std::invalid_argument) << bad;
  }
  // Too few neighbours for a plane: nothing flagged, also with a tiny multiplier.
  RadiusGraphParams params;
  params.residual_multiplier = 1e-6;
  const RadiusDegrees few = radiusGraphDegrees (noisySquare (4, 0.01f, 36), params);
  EXPECT_EQ (few.off_surface, std::vector<std::uint8_t> (4, 0));
}

TEST (Components, MatchABreadthFirstSearchOnAnyNumberOfThreads)
{
  // 150,000 vertices (the union-find works in blocks of 65,536): 400 components of random
  // members, each linked by a random tree (edges across blocks, in both directions of the
  // order), vertices without an edge, and zero-weight entries between components and to
  // otherwise unlinked vertices, which must join nothing.
  const std::size_t n = 150000;
  std::mt19937 rng (61);
  std::vector<int> label (n, -1);
  std::vector<std::vector<VertexIndex>> members (400);
  for (std::size_t v = 0; v < n; ++v)
    if (rng () % 10 != 0)
    {
      label[v] = static_cast<int> (rng () % members.size ());
      members[static_cast<std::size_t> (label[v])].push_back (static_cast<VertexIndex> (v));
    }
  std::vector<std::map<VertexIndex, float>> rows (n);
  const auto link = [&] (VertexIndex a, VertexIndex b, float w) {
    rows[a][b] = w;
    rows[b][a] = w;
  };
  for (auto &m : members)
  {
    std::shuffle (m.begin (), m.end (), rng);
    for (std::size_t r = 1; r < m.size (); ++r)
      link (m[r], m[rng () % r], 0.5f);
  }
  for (int e = 0; e < 5000; ++e)
  {
    const auto a = static_cast<VertexIndex> (rng () % n), b = static_cast<VertexIndex> (rng () % n);
    if (a != b && label[a] != label[b])
      link (a, b, 0.0f);
  }
  PointGraph graph;
  graph.order.resize (n);
  std::iota (graph.order.begin (), graph.order.end (), VertexIndex (0));
  graph.row_ptr.assign (1, 0);
  for (const auto &row : rows)
  {
    for (const auto &[j, w] : row)
    {
      graph.col.push_back (j);
      graph.weight.push_back (w);
    }
    graph.row_ptr.push_back (graph.col.size ());
  }
  // Breadth-first over the positive entries, from the smallest vertex of each component
  // (its label).
  GraphComponents expected;
  std::vector<std::uint8_t> seen (n, 0);
  std::vector<VertexIndex> label_of (n);
  for (std::size_t s = 0; s < n; ++s)
  {
    if (seen[s])
      continue;
    std::vector<std::size_t> queue{s};
    seen[s] = 1;
    for (std::size_t q = 0; q < queue.size (); ++q)
    {
      label_of[queue[q]] = static_cast<VertexIndex> (s);
      for (const auto &[j, w] : rows[queue[q]])
        if (w > 0.0f && !seen[j])
        {
          seen[j] = 1;
          queue.push_back (j);
        }
    }
    ++expected.count;
    expected.isolated += queue.size () == 1;
    expected.largest = std::max (expected.largest, queue.size ());
  }
  ASSERT_GT (expected.isolated, 10000u);  // the test's own premises
  ASSERT_LT (expected.count, 400u + expected.isolated + 1u);
  // Rows out of order (against PointGraph's contract) give the same components.
  PointGraph reversed = graph;
  for (std::size_t v = 0; v < n; ++v)
  {
    std::reverse (reversed.col.begin () + reversed.row_ptr[v], reversed.col.begin () + reversed.row_ptr[v + 1]);
    std::reverse (reversed.weight.begin () + reversed.row_ptr[v],
                  reversed.weight.begin () + reversed.row_ptr[v + 1]);
  }
  for (const int threads : {1, 2, 3, 0})
    for (const PointGraph *g : {&graph, &reversed})
    {
      const GraphComponents parts = connectedComponents (*g, threads);
      EXPECT_EQ (parts.count, expected.count) << threads;
      EXPECT_EQ (parts.isolated, expected.isolated) << threads;
      EXPECT_EQ (parts.largest, expected.largest) << threads;
      std::vector<std::uint8_t> linked;
      EXPECT_EQ (detail::componentRoots (*g, &linked, threads), label_of) << threads;
      for (std::size_t v = 0; v < n; ++v)
        ASSERT_EQ (linked[v] != 0, !rows[v].empty () && std::any_of (rows[v].begin (), rows[v].end (),
                                                                   [] (const auto &e) { return e.second > 0.0f; }))
            << v;
    }
}

class Operators : public ::testing::Test
{
protected:
  const PointGraph g = buildKnnGraph (randomPoints (3000, 14));
  const Signal3 x = randomSignal (3000, 15);
};

TEST_F (Operators, DegreeIsTheRowSum)
{
  const auto degree = weightedDegree (g);
  const auto edges = edgesInCallerOrder (g);
  std::vector<double> sums (3000, 0.0);
  for (const auto &e : edges)
    sums[e.first.first] += e.second;
  for (std::size_t v = 0; v < 3000; ++v)
    ASSERT_NEAR (degree[v], sums[g.order[v]], 1e-9);
}

TEST_F (Operators, LaplacianOfAConstantIsZero)
{
  Signal3 ones = Signal3::Ones (3000, 3), y;
  applyLaplacian (g, ones, y);
  EXPECT_LT (y.cwiseAbs ().maxCoeff (), 1e-12);
}

TEST_F (Operators, LaplacianMatchesDegreeMinusAdjacency)
{
  Signal3 y;
  applyLaplacian (g, x, y);
  const auto degree = weightedDegree (g);
  for (std::size_t i = 0; i < 3000; ++i)
  {
    Eigen::RowVector3d expected = degree[i] * x.row (i);
    for (auto e = g.row_ptr[i]; e < g.row_ptr[i + 1]; ++e)
      expected -= double (g.weight[e]) * x.row (g.col[e]);
    ASSERT_LT ((y.row (i) - expected).norm (), 1e-9);
  }
}

TEST_F (Operators, GradientNormEqualsLaplacianQuadraticForm)
{
  Signal3 grad, lx;
  applyGradient (g, x, grad);
  EXPECT_EQ (static_cast<std::size_t> (grad.rows ()), g.numEdges ());
  applyLaplacian (g, x, lx);
  const double quadratic = (x.array () * lx.array ()).sum ();
  EXPECT_NEAR (grad.squaredNorm (), quadratic, 1e-9 * quadratic);
}

TEST_F (Operators, GradientAdjointIsTheTranspose)
{
  Signal3 grad, back;
  applyGradient (g, x, grad);
  const Signal3 y = randomSignal (g.numEdges (), 16);
  applyGradientAdjoint (g, y, back);
  const double lhs = (grad.array () * y.array ()).sum ();
  const double rhs = (x.array () * back.array ()).sum ();
  EXPECT_NEAR (lhs, rhs, 1e-9 * std::abs (lhs));
  // grad^T grad = L.
  Signal3 gtg, lx;
  applyGradientAdjoint (g, grad, gtg);
  applyLaplacian (g, x, lx);
  EXPECT_LT ((gtg - lx).cwiseAbs ().maxCoeff (), 1e-9);
}

TEST_F (Operators, ResultsDoNotDependOnThreadCount)
{
  Signal3 a, b, ga, gb;
  applyLaplacian (g, x, a, 1);
  applyLaplacian (g, x, b, 3);
  EXPECT_TRUE (a == b);
  applyGradient (g, x, ga, 1);
  applyGradient (g, x, gb, 3);
  EXPECT_TRUE (ga == gb);
  EXPECT_EQ (weightedDegree (g, 1), weightedDegree (g, 4));
}

TEST_F (Operators, NormalizeDensityScalesEachSideOfAnEdgeByTheMeanDegreeOverItsOwn)
{
  const std::vector<double> degree = weightedDegree (g);
  double mean = 0.0;
  for (const double d : degree)
    mean += d;
  mean /= double (degree.size ());  // every vertex of this graph has links
  PointGraph normalized = g;
  normalizeDensity (normalized, 1.0, 1);
  EXPECT_EQ (normalized.col, g.col);
  EXPECT_EQ (normalized.row_ptr, g.row_ptr);
  EXPECT_EQ (normalized.order, g.order);
  std::vector<double> scale (degree.size ());
  std::size_t differs = 0;
  for (std::size_t i = 0; i < degree.size (); ++i)
    scale[i] = std::clamp (mean / degree[i], 1.0 / kDensityNormalizationLimit, kDensityNormalizationLimit);
  for (std::size_t i = 0; i < degree.size (); ++i)
    for (auto e = g.row_ptr[i]; e < g.row_ptr[i + 1]; ++e)
    {
      const VertexIndex j = g.col[e];
      ASSERT_EQ (normalized.weight[e], static_cast<float> (double (g.weight[e]) * (scale[i] * scale[j])));
      // Still symmetric, bit for bit.
      const auto back = std::lower_bound (g.col.begin () + g.row_ptr[j], g.col.begin () + g.row_ptr[j + 1],
                                          static_cast<VertexIndex> (i));
      ASSERT_EQ (normalized.weight[static_cast<std::size_t> (back - g.col.begin ())], normalized.weight[e]);
      differs += normalized.weight[e] != g.weight[e];
    }
  EXPECT_GT (differs, g.numEntries () / 2);  // a random sampling's degrees vary
  // The low-degree vertices gain the most: the degrees' spread narrows from below.
  const std::vector<double> after = weightedDegree (normalized);
  const auto lowest = std::min_element (degree.begin (), degree.end ()) - degree.begin ();
  EXPECT_GT (after[static_cast<std::size_t> (lowest)], degree[static_cast<std::size_t> (lowest)]);
  // The same on any number of threads.
  PointGraph threaded = g;
  normalizeDensity (threaded, 1.0, 3);
  EXPECT_TRUE (threaded.weight == normalized.weight);
  // A power below 1 takes that power of each side's factor; 0 leaves the weights.
  PointGraph half = g;
  normalizeDensity (half, 0.5);
  for (std::size_t i = 0; i < degree.size (); ++i)
    for (auto e = g.row_ptr[i]; e < g.row_ptr[i + 1]; ++e)
      ASSERT_EQ (half.weight[e], static_cast<float> (double (g.weight[e]) * (std::pow (scale[i], 0.5) *
                                                                            std::pow (scale[g.col[e]], 0.5))));
  PointGraph none = g;
  normalizeDensity (none, 0.0);
  EXPECT_TRUE (none.weight == g.weight);
  for (const double bad : {-0.1, 1.5, std::numeric_limits<double>::quiet_NaN ()})
    EXPECT_THROW (normalizeDensity (none, bad), std::invalid_argument) << bad;
}

TEST (DensityNormalization, LeavesAnEvenGraphClampsAndKeepsZerosAndIsolatedVertices)
{
  // Vertices 0-3: every pair linked with weight 0.5 (one degree: left as it is); vertex 4
  // linked to 0 only, by a weight of 1e-6 (its scale clamped to 16); vertex 5 isolated;
  // vertex 6 linked to 0 by a weight of 0 (stays 0).
  PointGraph graph;
  std::vector<std::vector<std::pair<VertexIndex, float>>> rows (7);
  for (VertexIndex i = 0; i < 4; ++i)
    for (VertexIndex j = 0; j < 4; ++j)
      if (i != j)
        rows[i].push_back ({j, 0.5f});
  const auto link = [&] (VertexIndex i, VertexIndex j, float w) {
    rows[i].push_back ({j, w});
    rows[j].push_back ({i, w});
  };
  PointGraph even;
  const auto store = [] (const std::vector<std::vector<std::pair<VertexIndex, float>>> &r, PointGraph &out) {
    out.row_ptr.assign (1, 0);
    for (std::size_t i = 0; i < r.size (); ++i)
    {
      auto sorted = r[i];
      std::sort (sorted.begin (), sorted.end ());
      for (const auto &entry : sorted)
      {
        out.col.push_back (entry.first);
        out.weight.push_back (entry.second);
      }
      out.row_ptr.push_back (out.col.size ());
      out.order.push_back (static_cast<VertexIndex> (i));
    }
  };
  store (std::vector<std::vector<std::pair<VertexIndex, float>>> (rows.begin (), rows.begin () + 4), even);
  const std::vector<float> even_weights = even.weight;
  normalizeDensity (even);
  EXPECT_TRUE (even.weight == even_weights);

  link (0, 4, 1e-6f);
  link (0, 6, 0.0f);
  store (rows, graph);
  const std::vector<double> degree = weightedDegree (graph);
  const double mean = (degree[0] + degree[1] + degree[2] + degree[3] + degree[4]) / 5.0;  // linked
  normalizeDensity (graph);
  const auto weightOf = [&] (VertexIndex i, VertexIndex j) {
    for (auto e = graph.row_ptr[i]; e < graph.row_ptr[i + 1]; ++e)
      if (graph.col[e] == j)
        return graph.weight[e];
    return -1.0f;
  };
  EXPECT_EQ (weightOf (0, 4), static_cast<float> (double (1e-6f) * ((mean / degree[0]) * kDensityNormalizationLimit)));
  EXPECT_EQ (weightOf (4, 0), weightOf (0, 4));
  EXPECT_EQ (weightOf (1, 2), static_cast<float> (0.5 * ((mean / degree[1]) * (mean / degree[2]))));
  EXPECT_EQ (weightOf (0, 6), 0.0f);
  EXPECT_EQ (weightOf (6, 0), 0.0f);
  EXPECT_EQ (graph.row_ptr[6], graph.row_ptr[5]);  // vertex 5: no entries

  PointGraph empty;
  normalizeDensity (empty);  // nothing to do, no failure
  EXPECT_TRUE (empty.weight.empty ());
}

TEST_F (Operators, RejectSignalsOfTheWrongSize)
{
  Signal3 y;
  EXPECT_THROW (applyLaplacian (g, Signal3::Zero (10, 3), y), std::invalid_argument);
  EXPECT_THROW (applyGradientAdjoint (g, Signal3::Zero (10, 3), y), std::invalid_argument);
}

TEST (Normals, PlaneNormalsAndTheirUse)
{
  // A tilted plane: every normal is +-n.
  std::mt19937 rng (61);
  std::uniform_real_distribution<float> u (-1.0f, 1.0f);
  const Eigen::Vector3d n = Eigen::Vector3d (1.0, 2.0, 3.0).normalized ();
  const Eigen::Vector3d a = n.unitOrthogonal (), b = n.cross (a);
  PointMatrix plane (2000, 3);
  for (Eigen::Index i = 0; i < plane.rows (); ++i)
    plane.row (i) = (u (rng) * a + u (rng) * b).cast<float> ().transpose ();
  const PointGraph graph = buildKnnGraph (plane);
  Signal3 f (plane.rows (), 3);
  for (Eigen::Index v = 0; v < plane.rows (); ++v)
    f.row (v) = plane.row (graph.order[v]).cast<double> ();
  const Signal3 normals = estimateNormals (graph, f);
  for (Eigen::Index v = 0; v < f.rows (); ++v)
  {
    ASSERT_NEAR (normals.row (v).norm (), 1.0, 1e-9);
    ASSERT_NEAR (std::abs (normals.row (v).dot (n.transpose ())), 1.0, 1e-5);
  }
  EXPECT_EQ (estimateNormals (graph, f, 1), estimateNormals (graph, f, 2));

  // The displacement keeps only its normal part.
  Signal3 x = f;
  x.col (0).array () += 0.1;
  const Signal3 moved = normalDisplacement (f, x, normals);
  for (Eigen::Index v = 0; v < f.rows (); ++v)
  {
    const Eigen::Vector3d d = (moved.row (v) - f.row (v)).transpose ();
    ASSERT_NEAR (d.cross (n).norm (), 0.0, 1e-5);  // along n
    ASSERT_NEAR (d.dot (n), 0.1 * n.x (), 1e-5);    // by the normal part of (0.1, 0, 0)
  }
  // A zero normal keeps the point; sizes must agree.
  const Signal3 none = Signal3::Zero (f.rows (), 3);
  EXPECT_EQ (normalDisplacement (f, x, none), f);
  EXPECT_THROW (normalDisplacement (f, x.topRows (3), normals), std::invalid_argument);
  EXPECT_THROW (estimateNormals (graph, f.topRows (3)), std::invalid_argument);
}

TEST (Normals, TooFewPointsGiveZeroNormals)
{
  PointMatrix two (2, 3);
  two << 0, 0, 0, 1, 0, 0;
  const PointGraph graph = buildKnnGraph (two);
  Signal3 f (2, 3);
  for (Eigen::Index v = 0; v < 2; ++v)
    f.row (v) = two.row (graph.order[v]).cast<double> ();
  EXPECT_EQ (estimateNormals (graph, f), Signal3::Zero (2, 3));
}

namespace {

/** Rows of `points` in the graph's vertex order. */
Signal3
inVertexOrder (const PointGraph &graph, const Signal3 &points)
{
  Signal3 out (points.rows (), 3);
  for (Eigen::Index v = 0; v < points.rows (); ++v)
    out.row (v) = points.row (graph.order[v]);
  return out;
}

} // namespace

TEST (Normals, QuadricDisplacementFollowsCurvatureWhereThePlaneCutsChords)
{
  // A coarse unit sphere: the estimate x is the clean points, f adds isotropic noise.
  // Moving f_i along the normal onto the plane through x_i leaves a chord error of
  // about |tangential offset|^2 / 2; the quadric keeps the curvature.
  std::mt19937 rng (71);
  std::normal_distribution<double> g (0.0, 1.0);
  const Eigen::Index n = 1500;
  Signal3 clean (n, 3), noisy (n, 3);
  for (Eigen::Index i = 0; i < n; ++i)
  {
    const Eigen::Vector3d p = Eigen::Vector3d (g (rng), g (rng), g (rng)).normalized ();
    clean.row (i) = p.transpose ();
    noisy.row (i) = (p + 0.05 * Eigen::Vector3d (g (rng), g (rng), g (rng))).transpose ();
  }
  const PointGraph graph = buildKnnGraph (clean.cast<float> ());
  const Signal3 x = inVertexOrder (graph, clean), f = inVertexOrder (graph, noisy);
  const auto mean_distance = [] (const Signal3 &s) {
    return (s.rowwise ().norm ().array () - 1.0).abs ().mean ();
  };
  const Signal3 quadric = quadricDisplacement (graph, f, x, 0.0);
  const Signal3 plane = normalDisplacement (f, x, estimateNormals (graph, x));
  std::printf ("distance to the sphere: noisy %.2e, plane %.2e, quadric %.2e\n", mean_distance (f),
               mean_distance (plane), mean_distance (quadric));
  EXPECT_LT (mean_distance (quadric), 0.2 * mean_distance (plane));
  EXPECT_LT (mean_distance (quadric), 2e-4);
  // Only along the normal (here about radial): the tangential position of f is kept.
  double sine = 0.0;
  for (Eigen::Index v = 0; v < n; ++v)
  {
    const Eigen::Vector3d d = (quadric.row (v) - f.row (v)).transpose ().normalized ();
    sine += d.cross (x.row (v).transpose ()).norm ();
  }
  EXPECT_LT (sine / double (n), 0.06);  // the patch normal, at its centroid: about 2 degrees off
  EXPECT_EQ (quadricDisplacement (graph, f, x, 0.01, 1), quadricDisplacement (graph, f, x, 0.01, 2));
  EXPECT_THROW (quadricDisplacement (graph, f.topRows (3), x, 0.0), std::invalid_argument);
  EXPECT_THROW (quadricDisplacement (graph, f, x.topRows (3), 0.0), std::invalid_argument);
}

TEST (Normals, RobustQuadricIgnoresTheOtherSheet)
{
  // Two parallel noisy sheets closer than the graph's reach: a plain fit over the rings
  // is pulled between them; re-weighted by the noise level, each point stays on its own.
  std::mt19937 rng (72);
  std::uniform_real_distribution<double> u (-1.0, 1.0);
  std::normal_distribution<double> g (0.0, 0.005);
  const Eigen::Index n = 4000;
  const double gap = 0.06;
  Signal3 points (n, 3);
  for (Eigen::Index i = 0; i < n; ++i)
    points.row (i) << u (rng), u (rng), (i % 2 ? gap : 0.0) + g (rng);
  const PointGraph graph = buildKnnGraph (points.cast<float> ());
  const Signal3 f = inVertexOrder (graph, points);
  const auto mean_off_sheet = [&] (const Signal3 &s) {
    double sum = 0.0;
    for (Eigen::Index v = 0; v < n; ++v)
      sum += std::abs (s (v, 2) - (graph.order[v] % 2 ? gap : 0.0));
    return sum / double (n);
  };
  const double plain = mean_off_sheet (quadricDisplacement (graph, f, f, 0.0));
  const double robust = mean_off_sheet (quadricDisplacement (graph, f, f, 0.005));
  const double blended =
      mean_off_sheet (quadricDisplacement (graph, f, f, 0.005, 0, QuadricProjection::BLENDED));
  std::printf ("distance to the own sheet: noisy %.2e, plain fit %.2e, robust %.2e, blended %.2e\n",
               mean_off_sheet (f), plain, robust, blended);
  EXPECT_GT (plain, 0.01);                      // dragged towards the other sheet
  EXPECT_LT (robust, 0.6 * mean_off_sheet (f));  // denoised on its own sheet
  // Blending: the other sheet's patches, a gap of 12 noise levels away, drop out.
  EXPECT_LT (blended, robust);
}

TEST (Normals, BlendedQuadricsAverageOutTheFitsNoise)
{
  // A noisy unit sphere fitted as it is (x = f): each vertex's own quadric carries the
  // noise of its 30-odd points; the mean of the overlapping fits around it carries less.
  std::mt19937 rng (74);
  std::normal_distribution<double> g (0.0, 1.0);
  const Eigen::Index n = 4000;
  const double noise = 0.01;
  Signal3 noisy (n, 3);
  for (Eigen::Index i = 0; i < n; ++i)
  {
    const Eigen::Vector3d p = Eigen::Vector3d (g (rng), g (rng), g (rng)).normalized ();
    noisy.row (i) = (p + noise * Eigen::Vector3d (g (rng), g (rng), g (rng))).transpose ();
  }
  const PointGraph graph = buildKnnGraph (noisy.cast<float> ());
  const Signal3 f = inVertexOrder (graph, noisy);
  const auto mean_distance = [] (const Signal3 &s) {
    return (s.rowwise ().norm ().array () - 1.0).abs ().mean ();
  };
  const Signal3 own = quadricDisplacement (graph, f, f, noise);
  const Signal3 blended = quadricDisplacement (graph, f, f, noise, 0, QuadricProjection::BLENDED);
  std::printf ("distance to the sphere: noisy %.2e, own patch %.2e, blended %.2e\n", mean_distance (f),
               mean_distance (own), mean_distance (blended));
  EXPECT_LT (mean_distance (blended), 0.9 * mean_distance (own));
  EXPECT_EQ (quadricDisplacement (graph, f, f, noise, 1, QuadricProjection::BLENDED),
             quadricDisplacement (graph, f, f, noise, 2, QuadricProjection::BLENDED));
  // The moves stay along the normals (here about radial): no drift along the surface.
  double sine = 0.0;
  for (Eigen::Index v = 0; v < n; ++v)
  {
    const Eigen::Vector3d d = (blended.row (v) - f.row (v)).transpose ().normalized ();
    sine += d.cross (f.row (v).transpose ().normalized ()).norm ();
  }
  EXPECT_LT (sine / double (n), 0.15);
}

TEST (Normals, TheKernelsExpMatchesTheLibrarysAndTheAvx2BuildTheBaseline)
{
  // The quadric fits' and the blend's weights come from detail::expOfNonPositive, plain
  // arithmetic the compiler vectorises: within a few units in the last place of
  // std::exp down to -708, 0 below it (and for NaN), exp(0) = 1 exactly.
  EXPECT_EQ (detail::expOfNonPositive (0.0), 1.0);
  EXPECT_EQ (detail::expOfNonPositive (-0.0), 1.0);
  EXPECT_EQ (detail::expOfNonPositive (-709.0), 0.0);
  EXPECT_EQ (detail::expOfNonPositive (-1e300), 0.0);
  EXPECT_EQ (detail::expOfNonPositive (-std::numeric_limits<double>::infinity ()), 0.0);
  EXPECT_EQ (detail::expOfNonPositive (std::numeric_limits<double>::quiet_NaN ()), 0.0);
  std::mt19937_64 rng (3);
  std::uniform_real_distribution<double> wide (-708.0, 0.0), near (-1.0, 0.0);
  double worst = 0.0;
  for (int trial = 0; trial < 200000; ++trial)
  {
    const double x = trial % 2 ? wide (rng) : near (rng);
    const double exact = std::exp (x);
    worst = std::max (worst, std::abs (detail::expOfNonPositive (x) - exact) / exact);
  }
  EXPECT_LT (worst, 5e-16);
  // The quadric step (robust fits, adaptive support, blend) gives the same bits in the
  // AVX2 build of its kernels and in the baseline one.
  if (!detail::setWideKernels (true))
    GTEST_SKIP () << "this processor has no AVX2: only the baseline build runs here";
  std::normal_distribution<double> g (0.0, 1.0);
  const Eigen::Index n = 3000;
  Signal3 noisy (n, 3);
  for (Eigen::Index i = 0; i < n; ++i)
  {
    const Eigen::Vector3d p = Eigen::Vector3d (g (rng), g (rng), g (rng)).normalized ();
    noisy.row (i) = (p + 0.01 * Eigen::Vector3d (g (rng), g (rng), g (rng))).transpose ();
  }
  const PointGraph graph = buildKnnGraph (noisy.cast<float> ());
  const Signal3 f = inVertexOrder (graph, noisy);
  const auto run = [&] () {
    return quadricDisplacement (graph, f, f, 0.01, 0, QuadricProjection::BLENDED,
                                QuadricSupport::ADAPTIVE, 3);
  };
  const Signal3 with_avx2 = run ();
  detail::setWideKernels (false);
  const Signal3 baseline = run ();
  detail::setWideKernels (true);
  EXPECT_TRUE (with_avx2 == baseline);
  EXPECT_FALSE (with_avx2 == f);
}

TEST (Normals, AdaptiveSupportWidensTheFitsOnlyWhereTheSurfaceIsSmoothAtThatScale)
{
  // Two noisy surfaces, each fitted as it is (x = f) with blended quadrics over two rings,
  // over three, and over the support chosen per vertex. On a unit sphere (it bends over
  // about 60 spacings) the wider fits average more noise; on a corrugated sheet (a period
  // of 8 spacings) they cut across the ridges and the narrow fits follow them. The
  // adaptive support must do as well as the better of the two on each.
  std::mt19937 rng (75);
  std::normal_distribution<double> g (0.0, 1.0);
  std::uniform_real_distribution<double> u (-1.0, 1.0);
  const Eigen::Index n = 4000;
  struct Surface
  {
    Signal3 noisy;
    double noise;
    std::function<double (const Eigen::Vector3d &)> distance;
  };
  Surface sphere{Signal3 (n, 3), 0.01, [] (const Eigen::Vector3d &p) { return std::abs (p.norm () - 1.0); }};
  const double spacing = std::sqrt (4.0 / double (n)), period = 8.0 * spacing, amplitude = spacing;
  const auto ridge = [=] (double a) { return amplitude * std::sin (2.0 * M_PI * a / period); };
  Surface sheet{Signal3 (n, 3), 0.1 * spacing, [=] (const Eigen::Vector3d &p) {
                  // Vertical offset times the cosine of the slope: the distance to first order.
                  const double slope = amplitude * 2.0 * M_PI / period * std::cos (2.0 * M_PI * p.x () / period);
                  return std::abs (p.z () - ridge (p.x ())) / std::sqrt (1.0 + slope * slope);
                }};
  for (Eigen::Index i = 0; i < n; ++i)
  {
    const Eigen::Vector3d s = Eigen::Vector3d (g (rng), g (rng), g (rng)).normalized ();
    sphere.noisy.row (i) = (s + sphere.noise * Eigen::Vector3d (g (rng), g (rng), g (rng))).transpose ();
    const double a = u (rng), b = u (rng);
    sheet.noisy.row (i) << a, b, ridge (a) + sheet.noise * g (rng);
  }
  double error[2][3];
  for (int which = 0; which < 2; ++which)
  {
    const Surface &surface = which == 0 ? sphere : sheet;
    const PointGraph graph = buildKnnGraph (surface.noisy.cast<float> ());
    const Signal3 f = inVertexOrder (graph, surface.noisy);
    int column = 0;
    for (const auto support : {QuadricSupport::TWO_RINGS, QuadricSupport::THREE_RINGS, QuadricSupport::ADAPTIVE})
    {
      const Signal3 out = quadricDisplacement (graph, f, f, surface.noise, 0, QuadricProjection::BLENDED, support);
      double sum = 0.0;
      for (Eigen::Index v = 0; v < n; ++v)
        sum += surface.distance (out.row (v).transpose ());
      error[which][column++] = sum / double (n);
    }
    std::printf ("%s: mean distance, two rings %.3e, three rings %.3e, adaptive %.3e\n",
                 which == 0 ? "sphere" : "corrugated sheet", error[which][0], error[which][1],
                 error[which][2]);
    EXPECT_EQ (quadricDisplacement (graph, f, f, surface.noise, 1, QuadricProjection::BLENDED, QuadricSupport::ADAPTIVE),
               quadricDisplacement (graph, f, f, surface.noise, 2, QuadricProjection::BLENDED, QuadricSupport::ADAPTIVE));
  }
  // The cases are telling: each support loses clearly on one surface.
  EXPECT_LT (error[0][1], 0.9 * error[0][0]);
  EXPECT_LT (error[1][0], 0.9 * error[1][1]);
  // The adaptive support is within 5% of the better one on both.
  EXPECT_LT (error[0][2], 1.05 * error[0][1]);
  EXPECT_LT (error[1][2], 1.05 * error[1][0]);
  // Without a noise level there is no test to widen by: two rings.
  const PointGraph graph = buildKnnGraph (sphere.noisy.cast<float> ());
  const Signal3 f = inVertexOrder (graph, sphere.noisy);
  EXPECT_EQ (quadricDisplacement (graph, f, f, 0.0, 0, QuadricProjection::BLENDED, QuadricSupport::ADAPTIVE),
             quadricDisplacement (graph, f, f, 0.0, 0, QuadricProjection::BLENDED, QuadricSupport::TWO_RINGS));
}

TEST (Normals, PatchCentresCoverEveryVertexAndBlendingThemLosesLittle)
{
  // A noisy sphere and the surface of a noisy cube (edges and corners): quadrics at the
  // patch centres only, blended, against a quadric at every vertex.
  std::mt19937 rng (76);
  std::normal_distribution<double> g (0.0, 1.0);
  std::uniform_real_distribution<double> u (-1.0, 1.0);
  const Eigen::Index n = 6000;
  const double noise = 0.01;
  Signal3 sphere (n, 3), cube (n, 3);
  for (Eigen::Index i = 0; i < n; ++i)
  {
    const Eigen::Vector3d s = Eigen::Vector3d (g (rng), g (rng), g (rng)).normalized ();
    sphere.row (i) = (s + noise * Eigen::Vector3d (g (rng), g (rng), g (rng))).transpose ();
    Eigen::Vector3d c (u (rng), u (rng), u (rng));
    const int face = static_cast<int> (i % 6);
    c (face / 2) = face % 2 ? 1.0 : -1.0;
    cube.row (i) = (c + noise * Eigen::Vector3d (g (rng), g (rng), g (rng))).transpose ();
  }
  const auto toSphere = [] (const Eigen::Vector3d &p) { return std::abs (p.norm () - 1.0); };
  const auto toCube = [] (const Eigen::Vector3d &p) {
    const Eigen::Vector3d a = p.cwiseAbs ();
    if ((a.array () <= 1.0).all ())
      return 1.0 - a.maxCoeff ();
    return (a.array () - 1.0).max (0.0).matrix ().norm ();
  };
  for (int which = 0; which < 2; ++which)
  {
    const Signal3 &points = which == 0 ? sphere : cube;
    const PointGraph graph = buildKnnGraph (points.cast<float> ());
    const Signal3 f = inVertexOrder (graph, points);
    const std::size_t count = graph.numVertices ();

    // The rule: every vertex carries a patch (cover 0), or it has at least `cover`
    // neighbours that do; a vertex carries one when fewer than `cover` of its neighbours
    // before it did. The larger the cover, the more centres.
    EXPECT_EQ (patchCentres (graph, 0), std::vector<std::uint8_t> (count, 1));
    EXPECT_THROW (patchCentres (graph, -1), std::invalid_argument);
    std::size_t previous = 0;
    for (const int cover : {1, 2, 3, 5})
    {
      const std::vector<std::uint8_t> centre = patchCentres (graph, cover);
      ASSERT_EQ (centre.size (), count);
      std::size_t centres = 0;
      for (std::size_t v = 0; v < count; ++v)
      {
        int around = 0, before = 0;
        for (std::uint64_t e = graph.row_ptr[v]; e < graph.row_ptr[v + 1]; ++e)
        {
          around += centre[graph.col[e]];
          before += centre[graph.col[e]] && graph.col[e] < v;
        }
        if (centre[v])
          EXPECT_LT (before, cover) << "vertex " << v;
        else
          EXPECT_GE (before, cover) << "vertex " << v;
        EXPECT_TRUE (centre[v] || around >= cover);
        centres += centre[v];
      }
      EXPECT_GT (centres, previous) << "cover " << cover;
      EXPECT_LT (centres, count) << "cover " << cover;
      previous = centres;
    }

    const auto error = [&] (const Signal3 &out) {
      double sum = 0.0;
      for (Eigen::Index v = 0; v < out.rows (); ++v)
        sum += (which == 0 ? toSphere : toCube) (out.row (v).transpose ());
      return sum / double (out.rows ());
    };
    const auto blend = [&] (int cover, int threads) {
      return quadricDisplacement (graph, f, f, noise, threads, QuadricProjection::BLENDED,
                                  QuadricSupport::ADAPTIVE, cover);
    };
    const Signal3 every = blend (0, 0), shared = blend (3, 1);
    EXPECT_EQ (every, quadricDisplacement (graph, f, f, noise, 0, QuadricProjection::BLENDED,
                                           QuadricSupport::ADAPTIVE));
    EXPECT_EQ (shared, blend (3, 2));
    EXPECT_NE (shared, every);
    std::printf ("%s: mean distance, a quadric at every vertex %.4e, at the centres of cover 3 "
                 "%.4e (noisy %.4e)\n",
                 which == 0 ? "sphere" : "cube", error (every), error (shared), error (f));
    EXPECT_LT (error (shared), 1.03 * error (every));
    EXPECT_LT (error (shared), 0.5 * error (f));
    // Without a blend every point needs its own quadric: the cover changes nothing.
    EXPECT_EQ (quadricDisplacement (graph, f, f, noise, 0, QuadricProjection::OWN_PATCH,
                                    QuadricSupport::ADAPTIVE, 3),
               quadricDisplacement (graph, f, f, noise, 0, QuadricProjection::OWN_PATCH,
                                    QuadricSupport::ADAPTIVE));
    EXPECT_THROW (blend (-1, 0), std::invalid_argument);
  }
}

TEST (Normals, QuadricWithTooFewPointsKeepsTheEstimate)
{
  Signal3 f (2, 3), x (2, 3);
  f << 0, 0, 0, 1, 0, 0;
  x << 0, 0.1, 0, 1, 0.1, 0;
  const PointGraph graph = buildKnnGraph (f.cast<float> ());
  for (const auto projection : {QuadricProjection::OWN_PATCH, QuadricProjection::BLENDED})
    EXPECT_EQ (quadricDisplacement (graph, inVertexOrder (graph, f), inVertexOrder (graph, x), 0.0, 0,
                                    projection),
               inVertexOrder (graph, x));
  // With a cover of 1 the second point carries no quadric and borrows none: it keeps x too.
  EXPECT_EQ (patchCentres (graph, 1), (std::vector<std::uint8_t>{1, 0}));
  EXPECT_EQ (quadricDisplacement (graph, inVertexOrder (graph, f), inVertexOrder (graph, x), 0.01, 0,
                                  QuadricProjection::BLENDED, QuadricSupport::ADAPTIVE, 1),
             inVertexOrder (graph, x));
}

TEST (Normals, QuadricIsNotExtrapolatedFromACollapsedPatch)
{
  // A very strong TV solve collapses whole neighbourhoods onto one point: the rings of x
  // then span a micrometre while f_i lies a unit away. Evaluating the fitted quadric
  // there would throw f_i arbitrarily far (it did, by up to 6,000 units on a real
  // cloud); the displacement must stay within f_i's distance to x_i plus 3 noise levels.
  std::mt19937 rng (73);
  std::uniform_real_distribution<double> u (-1.0, 1.0);
  std::normal_distribution<double> g (0.0, 1.0);
  const Eigen::Index n = 500;
  const double noise = 0.01;
  Signal3 points (n, 3), collapsed (n, 3);
  for (Eigen::Index i = 0; i < n; ++i)
  {
    points.row (i) << u (rng), u (rng), noise * g (rng);
    collapsed.row (i) << 1e-6 * g (rng), 1e-6 * g (rng), 1e-6 * g (rng);
  }
  const PointGraph graph = buildKnnGraph (points.cast<float> ());
  const Signal3 f = inVertexOrder (graph, points), x = inVertexOrder (graph, collapsed);
  // With the noise level (as the filters call it), and without: the quadric is then
  // evaluated on the patch only, where it stays within a micrometre of x.
  for (const double level : {noise, 0.0})
    for (const auto projection : {QuadricProjection::OWN_PATCH, QuadricProjection::BLENDED})
      for (const auto support : {QuadricSupport::TWO_RINGS, QuadricSupport::ADAPTIVE})
      {
        const Signal3 out = quadricDisplacement (graph, f, x, level, 0, projection, support);
        ASSERT_TRUE (out.allFinite ());
        double worst = 0.0;
        for (Eigen::Index v = 0; v < n; ++v)
          worst = std::max (worst, (out.row (v) - f.row (v)).norm () -
                                       ((f.row (v) - x.row (v)).norm () + 3.0 * noise));
        EXPECT_LE (worst, 0.0) << "noise level " << level << ", blended "
                               << (projection == QuadricProjection::BLENDED);
      }
}

namespace {

PointMatrix
matrixOf (const pcl::PointCloud<pcl::PointXYZ> &cloud, const Eigen::Isometry3d &pose =
                                                          Eigen::Isometry3d::Identity ())
{
  PointMatrix m (static_cast<Eigen::Index> (cloud.size ()), 3);
  for (std::size_t i = 0; i < cloud.size (); ++i)
    m.row (static_cast<Eigen::Index> (i)) =
        (pose * cloud[i].getVector3fMap ().cast<double> ()).cast<float> ().transpose ();
  return m;
}

/** Mean of `distance` over the rows of p + offsets. */
template <typename Distance>
double
meanDistanceAfter (const PointMatrix &p, const Signal3 &offsets, Distance distance)
{
  double sum = 0.0;
  for (Eigen::Index i = 0; i < p.rows (); ++i)
    sum += distance (Eigen::Vector3d (p.row (i).transpose ().cast<double> () +
                                      offsets.row (i).transpose ()));
  return sum / double (p.rows ());
}

} // namespace

TEST (SurfaceOffsets, BringARigidlyMovedCubeOntoTheReferenceSurface)
{
  // The reference: a noisy cube. The moving frame: another noisy sample of it, turned 4
  // degrees and shifted by 5 sigma: every face has moved off itself.
  const double noise = 0.01;
  const PointMatrix reference = matrixOf (synthetic::noisyCube (6000, noise, 1));
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity ();
  pose.translate (Eigen::Vector3d (0.05, -0.03, 0.02));
  pose.rotate (Eigen::AngleAxisd (4.0 * M_PI / 180.0, Eigen::Vector3d (0.2, 0.3, 1.0).normalized ()));
  const PointMatrix moving = matrixOf (synthetic::noisyCube (6000, noise, 2), pose);
  const auto to_cube = [] (const Eigen::Vector3d &p) { return synthetic::distanceToCube (p); };
  const Signal3 none = Signal3::Zero (moving.rows (), 3);
  const double noisy = meanDistanceAfter (reference, Signal3::Zero (reference.rows (), 3), to_cube);
  const double before = meanDistanceAfter (moving, none, to_cube);
  const Signal3 offsets = surfaceOffsets (moving, reference);
  const double after = meanDistanceAfter (moving, offsets, to_cube);
  EXPECT_GT (before, 3.0 * noisy);
  EXPECT_LT (after, 1.15 * noisy) << "noise alone " << noisy << ", moved " << before;

  // Without the rigid rounds, the offsets along the normals alone still bring most of
  // the faces back (not the edges, where the normals are mixed).
  SurfaceOffsetParams local_only;
  local_only.rigid_iterations = 0;
  const double local = meanDistanceAfter (moving, surfaceOffsets (moving, reference, local_only), to_cube);
  EXPECT_LT (local, 0.5 * before);
  EXPECT_GT (local, after);
}

TEST (SurfaceOffsets, FollowADeformationThatNoRigidMotionExplains)
{
  // A sphere grown by 4% (5 sigma) against the unit sphere: no rigid motion helps, the
  // offsets along the normals do.
  const double noise = 0.008;
  const PointMatrix reference = matrixOf (synthetic::noisySphere (5000, 1.0, noise, 3));
  const PointMatrix moving = matrixOf (synthetic::noisySphere (5000, 1.04, noise, 4));
  const auto to_sphere = [] (const Eigen::Vector3d &p) { return std::abs (p.norm () - 1.0); };
  const Signal3 offsets = surfaceOffsets (moving, reference);
  const double before = meanDistanceAfter (moving, Signal3::Zero (moving.rows (), 3), to_sphere);
  const double after = meanDistanceAfter (moving, offsets, to_sphere);
  EXPECT_GT (before, 0.035);
  EXPECT_LT (after, 1.2 * noise * std::sqrt (2.0 / M_PI)) << "before " << before;
}

TEST (SurfaceOffsets, LeaveASurfaceThatDidNotMoveWhereItIs)
{
  // Two noisy samples of one sphere: the offsets are noise, shrunk to a small fraction of
  // sigma along the normal (a turn about the centre, which maps the sphere onto itself,
  // is allowed and harmless: only the radial part counts).
  const double noise = 0.01;
  const PointMatrix reference = matrixOf (synthetic::noisySphere (5000, 1.0, noise, 5));
  const PointMatrix moving = matrixOf (synthetic::noisySphere (5000, 1.0, noise, 6));
  const Signal3 offsets = surfaceOffsets (moving, reference);
  double radial = 0.0;
  for (Eigen::Index i = 0; i < moving.rows (); ++i)
  {
    const Eigen::Vector3d p = moving.row (i).transpose ().cast<double> ();
    radial += std::abs ((p + offsets.row (i).transpose ()).norm () - p.norm ());
  }
  EXPECT_LT (radial / double (moving.rows ()), 0.2 * noise);
}

TEST (SurfaceOffsets, LeaveASurfaceSampledAtAnotherDensityWhereItIs)
{
  // One still sphere in two frames, one four times as dense as the other. The k nearest
  // points of each frame span disks of different sizes, whose means lie below the
  // sphere by different amounts: compared as they were, that read the curvature as an
  // offset (the sparser frame's points moved out by about its noise level) and the
  // rigid fit turned a noisy rotation of 0.05 into motion. Both frames are now compared
  // over the same disk and the rigid motion is shrunk by its own significance.
  const double noise = 0.01;
  const PointMatrix sparse = matrixOf (synthetic::noisySphere (1000, 1.0, noise, 5));
  const PointMatrix dense = matrixOf (synthetic::noisySphere (4000, 1.0, noise, 6));
  for (const bool sparse_moves : {true, false})
  {
    const PointMatrix &moving = sparse_moves ? sparse : dense;
    const Signal3 offsets = surfaceOffsets (moving, sparse_moves ? dense : sparse);
    double radial = 0.0, moved = 0.0;
    for (Eigen::Index i = 0; i < moving.rows (); ++i)
    {
      const Eigen::Vector3d p = moving.row (i).transpose ().cast<double> ();
      radial += std::abs ((p + offsets.row (i).transpose ()).norm () - p.norm ());
      moved += offsets.row (i).norm ();
    }
    EXPECT_LT (radial / double (moving.rows ()), 0.2 * noise) << "sparse moves: " << sparse_moves;
    EXPECT_LT (moved / double (moving.rows ()), 0.3 * noise) << "sparse moves: " << sparse_moves;
  }
}

TEST (SurfaceOffsets, LeaveAStillCubeWhereItIsAtItsEdges)
{
  // One still cube in two frames of the same density. Near an edge the disk compared
  // across the normal takes in points of the other face beyond a point's k nearest:
  // taken so for the reference only (its 2k nearest) and not for the moving frame (its
  // k nearest), the two neighbourhoods differed and the edges read as an offset of
  // about half the noise level. Both are now taken from the same pool and ball.
  const double noise = 0.005;
  const PointMatrix moving = matrixOf (synthetic::noisyCube (5000, noise, 11));
  const Signal3 offsets = surfaceOffsets (moving, matrixOf (synthetic::noisyCube (5000, noise, 99)));
  double edges = 0.0;
  int count = 0;
  for (Eigen::Index i = 0; i < moving.rows (); ++i)
  {
    int faces = 0;
    for (int c = 0; c < 3; ++c)
      faces += std::abs (std::abs (moving (i, c)) - 1.0f) < 0.1f;
    if (faces >= 2)
    {
      edges += offsets.row (i).norm ();
      ++count;
    }
  }
  ASSERT_GT (count, 500);
  EXPECT_LT (edges / count, 0.25 * noise);
}

TEST (SurfaceOffsets, MeasureAnOffsetLargerThanTheNeighbourhood)
{
  // A plane lifted by 0.2, twice the reach of its points' 30 nearest (spacing 0.03):
  // the reference's points are compared over a ball around the moving point moved by
  // the two neighbourhoods' offset, not around the point itself, which holds none of
  // them. Without the rigid rounds, so that the local offsets alone carry it.
  const double noise = 0.005, lift = 0.2;
  Eigen::Isometry3d up = Eigen::Isometry3d::Identity ();
  up.translate (Eigen::Vector3d (0.0, 0.0, lift));
  const PointMatrix moving = matrixOf (synthetic::noisyPlane (4000, noise, 21));
  SurfaceOffsetParams params;
  params.rigid_iterations = 0;
  const Signal3 offsets = surfaceOffsets (moving, matrixOf (synthetic::noisyPlane (4000, noise, 22), up), params);
  EXPECT_NEAR (offsets.col (2).mean (), lift, 0.02 * lift);
  // Along the normal, up to the tilt of its estimate, away from the plane's border
  // (whose normals tilt further).
  double sideways = 0.0;
  int inner = 0;
  for (Eigen::Index i = 0; i < moving.rows (); ++i)
    if (moving.row (i).head<2> ().cwiseAbs ().maxCoeff () < 0.8f)
    {
      sideways += offsets.row (i).head<2> ().norm ();
      ++inner;
    }
  EXPECT_LT (sideways / inner, 0.02 * lift);
}

TEST (SurfaceOffsets, NoOffsetWhereTheReferenceDoesNotCoverTheSurface)
{
  // The reference covers x < 0 of a plane; the moving frame is the whole plane lifted by
  // 0.05 (10 sigma). Without the rigid rounds, the covered part comes down and the far
  // part, with no counterpart, stays.
  const double noise = 0.005;
  const pcl::PointCloud<pcl::PointXYZ> plane = synthetic::noisyPlane (8000, noise, 7);
  pcl::PointCloud<pcl::PointXYZ> half;
  for (const auto &p : synthetic::noisyPlane (8000, noise, 8))
    if (p.x < 0.0f)
      half.push_back (p);
  Eigen::Isometry3d lift = Eigen::Isometry3d::Identity ();
  lift.translate (Eigen::Vector3d (0.0, 0.0, 0.05));
  const PointMatrix moving = matrixOf (plane, lift);
  SurfaceOffsetParams params;
  params.rigid_iterations = 0;
  const Signal3 offsets = surfaceOffsets (moving, matrixOf (half), params);
  int covered = 0, uncovered = 0;
  for (Eigen::Index i = 0; i < moving.rows (); ++i)
  {
    if (moving (i, 0) < -0.3f)
    {
      EXPECT_NEAR (offsets (i, 2), -0.05, 0.01) << "row " << i;
      ++covered;
    }
    else if (moving (i, 0) > 0.5f)
    {
      EXPECT_LT (offsets.row (i).norm (), 0.01) << "row " << i;
      ++uncovered;
    }
  }
  EXPECT_GT (covered, 1000);
  EXPECT_GT (uncovered, 1000);
  // With them, the rigid lift found on the covered half moves the whole plane down.
  const Signal3 rigid = surfaceOffsets (moving, matrixOf (half));
  for (Eigen::Index i = 0; i < moving.rows (); ++i)
    if (moving (i, 0) > 0.5f)
      EXPECT_NEAR (rigid (i, 2), -0.05, 0.01) << "row " << i;
}

TEST (SurfaceOffsets, ThreadsDegenerateCloudsAndInvalidParameters)
{
  const PointMatrix reference = matrixOf (synthetic::noisyCube (3000, 0.01, 9));
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity ();
  pose.translate (Eigen::Vector3d (0.03, 0.0, 0.0));
  const PointMatrix moving = matrixOf (synthetic::noisyCube (3000, 0.01, 10), pose);
  SurfaceOffsetParams one, two;
  one.num_threads = 1;
  two.num_threads = 2;
  const Signal3 a = surfaceOffsets (moving, reference, one);
  EXPECT_TRUE (a == surfaceOffsets (moving, reference, two));
  EXPECT_GT (a.rowwise ().norm ().mean (), 0.01);

  // Units do not matter: the same clouds in millimetres give the offsets in millimetres.
  const Signal3 scaled = surfaceOffsets (PointMatrix (1000.0f * moving), PointMatrix (1000.0f * reference), one);
  EXPECT_LT ((scaled - 1000.0 * a).cwiseAbs ().maxCoeff (), 1e-3 * 1000.0 * a.cwiseAbs ().maxCoeff ());

  // Fewer than 3 points on either side: nothing to compare, no offset.
  EXPECT_TRUE (surfaceOffsets (moving, reference.topRows (2)).isZero ());
  EXPECT_EQ (surfaceOffsets (moving.topRows (2), reference).rows (), 2);
  EXPECT_TRUE (surfaceOffsets (moving.topRows (2), reference).isZero ());
  EXPECT_EQ (surfaceOffsets (PointMatrix (0, 3), reference).rows (), 0);

  SurfaceOffsetParams bad;
  bad.k = 2;
  EXPECT_THROW (surfaceOffsets (moving, reference, bad), std::invalid_argument);
  bad = SurfaceOffsetParams ();
  bad.significance = std::numeric_limits<double>::quiet_NaN ();
  EXPECT_THROW (surfaceOffsets (moving, reference, bad), std::invalid_argument);
  bad.significance = -1.0;
  EXPECT_THROW (surfaceOffsets (moving, reference, bad), std::invalid_argument);
  bad = SurfaceOffsetParams ();
  bad.rigid_iterations = -1;
  EXPECT_THROW (surfaceOffsets (moving, reference, bad), std::invalid_argument);
  bad = SurfaceOffsetParams ();
  bad.num_threads = -1;
  EXPECT_THROW (surfaceOffsets (moving, reference, bad), std::invalid_argument);
  PointMatrix nan = moving;
  nan (5, 1) = std::numeric_limits<float>::quiet_NaN ();
  EXPECT_THROW (surfaceOffsets (nan, reference), std::invalid_argument);
  EXPECT_THROW (surfaceOffsets (moving, nan), std::invalid_argument);
}

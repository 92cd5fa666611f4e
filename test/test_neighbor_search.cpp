/*
 * pcl_graph_denoise: graph-signal-processing point cloud denoising for PCL.
 * SPDX-License-Identifier: BSD-3-Clause
 *
 * The private all-points k-NN search of the core (src/core/neighbor_search.h) against
 * brute force, row by row, on the clouds where its grid and its k-d tree are most
 * likely to go wrong: the result must be exactly the k nearest by (single-precision
 * squared distance, vertex), whatever the number of threads. Compiled with
 * -ffp-contract=off, as the search is, so that both compute the same distances.
 * Also the graph rings of the quadric fits and the noise estimate (src/core/two_ring.h).
 */
#include <pcl_graph_denoise/core/graph.h>

#include "neighbor_search.h"
#include "spatial_order.h"
#include "two_ring.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <string>
#include <vector>

using namespace pcl_graph_denoise::core;
using namespace pcl_graph_denoise::core::detail;

namespace {

/** Every point's k nearest others by (float squared distance, vertex), in the order of
 *  `sorted`, as rows of k; and each row's mean distance. */
void
bruteForce (const PointMatrix &p, int k, std::vector<VertexIndex> &indices, std::vector<double> &mean)
{
  const auto n = static_cast<std::size_t> (p.rows ());
  indices.assign (n * k, 0);
  mean.assign (n, 0.0);
  std::vector<std::pair<float, VertexIndex>> all;
  for (std::size_t v = 0; v < n; ++v)
  {
    all.clear ();
    for (std::size_t w = 0; w < n; ++w)
      if (w != v)
      {
        const float dx = p (v, 0) - p (w, 0), dy = p (v, 1) - p (w, 1), dz = p (v, 2) - p (w, 2);
        all.emplace_back (dx * dx + dy * dy + dz * dz, static_cast<VertexIndex> (w));
      }
    std::partial_sort (all.begin (), all.begin () + k, all.end ());
    double sum = 0.0;
    for (int m = 0; m < k; ++m)
    {
      indices[v * k + m] = all[m].second;
      sum += std::sqrt (double (all[m].first));
    }
    mean[v] = sum / k;
  }
}

/** allNearestOthers on `raw` equals brute force on 1 and 3 threads, and takes the same
 *  paths on both; returns them. */
NearestOthersPaths
expectExact (const PointMatrix &raw, int k, const std::string &what)
{
  NearestOthersPaths paths[2];
  const MortonSort sorted = mortonSort (raw, 1);
  const PointMatrix points = reorderPoints (raw, sorted.order);
  const auto n = static_cast<std::size_t> (points.rows ());
  std::vector<VertexIndex> want;
  std::vector<double> want_mean;
  bruteForce (points, k, want, want_mean);
  for (const int threads : {1, 3})
  {
    std::vector<VertexIndex> got (n * k);
    std::vector<double> mean (n);
    allNearestOthers (points, sorted, k, threads, got.data (), mean.data (),
                      &paths[threads == 1 ? 0 : 1]);
    std::size_t wrong = 0, first = n;
    for (std::size_t v = 0; v < n; ++v)
      if (!std::equal (got.begin () + v * k, got.begin () + (v + 1) * k, want.begin () + v * k) ||
          mean[v] != want_mean[v])
      {
        first = std::min (first, v);
        ++wrong;
      }
    EXPECT_EQ (wrong, 0u) << what << ", k = " << k << ", " << threads << " threads: " << wrong
                          << " rows differ, the first at vertex " << first;
  }
  EXPECT_EQ (paths[0].grid, paths[1].grid) << what;
  EXPECT_EQ (paths[0].coarser, paths[1].coarser) << what;
  EXPECT_EQ (paths[0].scanned, paths[1].scanned) << what;
  EXPECT_EQ (paths[0].tree, paths[1].tree) << what;
  EXPECT_EQ (paths[0].grid + paths[0].coarser + paths[0].scanned + paths[0].tree, n) << what;
  return paths[0];
}

} // namespace

TEST (AllNearestOthers, ExactWherePointsLieJustBeyondTheirCellsComputedFaces)
{
  // Two anchors a million units out make the grid's faces (lo + m * width, in double
  // precision) uncertain by about 1e-10, while three points near x = 2.19, a few 1e-7
  // apart, straddle a face: p sits in the cell beyond it by its code but below the face
  // as computed. q's nearest is p (a cell skipped as too far, had the faces' error been
  // ignored), not r. 200 groups of 5 copies fix the grid's level at the finest.
  PointMatrix p (1005, 3);
  int row = 0;
  p.row (row++) << -1e6f, 1.2e6f, 1.2e6f;
  p.row (row++) << 1010935.75f, 1.2e6f, 1.1e6f;
  for (int group = 0; group < 200; ++group)
    for (int copy = 0; copy < 5; ++copy)
      p.row (row++) << -9e5f + 9000.0f * group, 1e6f + 100.0f * group, 1e6f;
  p.row (row++) << 2.1874845f, 0.0f, 0.0f;
  p.row (row++) << 2.1874826f, 1.42779362e-08f, 0.0f;
  p.row (row++) << 2.18748641f, 0.0f, 0.0f;
  for (const int k : {1, 2, 6})
    expectExact (p, k, "faces a million units out");
}

TEST (AllNearestOthers, ExactWhereSquaredDistancesUnderflow)
{
  // In a box 1e-22 wide the squared distances are subnormal floats or 0: a cell whose
  // distance is 1e-46 may still hold a point at a float distance of 0.
  std::mt19937 rng (3);
  std::uniform_real_distribution<float> u (0.0f, 1e-22f);
  PointMatrix p (1500, 3);
  for (Eigen::Index i = 0; i < p.rows (); ++i)
    p.row (i) << u (rng), u (rng), u (rng);
  for (const int k : {1, 4, 10, 30})
    expectExact (p, k, "a box 1e-22 wide");
}

TEST (AllNearestOthers, ExactAmongTiesInTheTree)
{
  // Lattices of 1,200 points (many exact ties) with two points 1e7 away: the far points
  // stretch the grid until the lattice fills crowded cells, so every point goes to the
  // k-d tree, whose own k-NN keeps any one of the points tied at the k-th distance.
  for (const unsigned seed : {9u, 49u, 91u})
  {
    std::mt19937 rng (seed);
    std::uniform_real_distribution<float> u (0.0f, 1.0f);
    PointMatrix p (1200, 3);
    const float step = 0.1f + 0.9f * u (rng), offset = 100.0f * u (rng);
    const unsigned side = 4 + rng () % 8;
    for (Eigen::Index i = 0; i < p.rows (); ++i)
    {
      const unsigned a = rng () % side, b = rng () % side, c = rng () % side;
      p.row (i) << offset + step * a, 0.3f * offset + 1.3f * step * b, 0.7f * step * c;
      if (rng () % 4 == 0)
        p (i, rng () % 3) += 0.5f * step * float (rng () % 3);
    }
    p.row (0) << 1e7f, 0.0f, 0.0f;
    p.row (1) << -1e7f, 0.0f, 0.0f;
    for (const int k : {1, 7, 30})
      EXPECT_GT (expectExact (p, k, "a lattice with far points, seed " + std::to_string (seed)).tree,
                 16u);
  }
}

TEST (AllNearestOthers, ExactOnCopiesOutliersAndCoincidentPoints)
{
  std::mt19937 rng (5);
  std::normal_distribution<float> g (0.0f, 1.0f);
  std::uniform_real_distribution<float> u (-1.2f, 1.2f);
  // A noisy sphere with outliers, each point three times.
  PointMatrix sphere (2000, 3);
  for (Eigen::Index i = 0; i < sphere.rows (); ++i)
  {
    const Eigen::Vector3f s = Eigen::Vector3f (g (rng), g (rng), g (rng)).normalized ();
    const Eigen::Vector3f box (u (rng), u (rng), u (rng));
    sphere.row (i) = (i % 25 == 0 ? box : Eigen::Vector3f (s + 0.01f * Eigen::Vector3f (g (rng), g (rng), g (rng))))
                         .transpose ();
  }
  PointMatrix copies (6000, 3);
  copies << sphere, sphere, sphere;
  for (const int k : {2, 10})
    expectExact (copies, k, "copies of a sphere with outliers");
  // Every point at one of two positions, and every point at one position.
  PointMatrix two (400, 3), one = PointMatrix::Constant (300, 3, 2.5f);
  for (Eigen::Index i = 0; i < two.rows (); ++i)
    two.row (i) << float (i % 2), 0.0f, 0.0f;
  expectExact (two, 10, "two positions");
  expectExact (one, 10, "one position");
}

TEST (AllNearestOthers, ExactOnEveryPath)
{
  // A square of 10,000 points and, beside it, one 20 times sparser: the grid's cells fit
  // the dense square, where the sparse one's k-th neighbours often lie beyond the 27
  // cells around a point's own; the next coarser grid settles those.
  std::mt19937 rng (17);
  std::uniform_real_distribution<float> u (0.0f, 1.0f);
  PointMatrix squares (12000, 3);
  for (Eigen::Index i = 0; i < squares.rows (); ++i)
  {
    if (i < 10000)
      squares.row (i) << u (rng), u (rng), 0.0f;
    else
      squares.row (i) << 2.0f + 2.0f * u (rng), 2.0f * u (rng), 0.0f;
  }
  for (const int k : {7, 10})
  {
    const NearestOthersPaths paths = expectExact (squares, k, "a dense and a sparse square");
    EXPECT_GT (paths.coarser, 100u) << "k = " << k;
    EXPECT_EQ (paths.tree, 0u) << "k = " << k;
  }
  // A cube of points and five far ones, alone in their cells at every level tried: they
  // are compared with every point, and no k-d tree is built.
  PointMatrix cube (3005, 3);
  for (Eigen::Index i = 0; i < 3000; ++i)
    cube.row (i) << u (rng), u (rng), u (rng);
  cube.row (3000) << 60.0f, 0.5f, 0.5f;
  cube.row (3001) << -40.0f, 0.5f, 0.5f;
  cube.row (3002) << 0.5f, 70.0f, 0.5f;
  cube.row (3003) << 0.5f, -50.0f, 30.0f;
  cube.row (3004) << 0.5f, 0.5f, -45.0f;
  for (const int k : {1, 10})
  {
    const NearestOthersPaths paths = expectExact (cube, k, "a cube and five far points");
    EXPECT_EQ (paths.scanned, 5u) << "k = " << k;
    EXPECT_EQ (paths.tree, 0u) << "k = " << k;
  }
}

// The graph rings of the quadric fits and the noise estimate (src/core/two_ring.h).

namespace {

/** A k-NN graph of a seeded random cloud, and its points as a signal. */
PointGraph
ringGraph (Signal3 &x)
{
  std::mt19937 rng (5);
  std::normal_distribution<float> g (0.0f, 1.0f);
  PointMatrix p (400, 3);
  for (Eigen::Index r = 0; r < p.rows (); ++r)
    p.row (r) << g (rng), g (rng), 0.1f * g (rng);
  KnnGraphParams params;
  params.k = 6;
  PointGraph graph = buildKnnGraph (p, params);
  x.resize (p.rows (), 3);
  for (std::size_t v = 0; v < graph.numVertices (); ++v)
    x.row (static_cast<Eigen::Index> (v)) = p.row (graph.order[v]).cast<double> ();
  return graph;
}

/** The vertices within `hops` graph links of v, by breadth-first search. */
std::vector<VertexIndex>
within (const PointGraph &graph, VertexIndex v, int hops)
{
  std::vector<VertexIndex> out{v};
  std::vector<int> depth (graph.numVertices (), -1);
  depth[v] = 0;
  for (std::size_t r = 0; r < out.size (); ++r)
  {
    const VertexIndex u = out[r];
    if (depth[u] == hops)
      continue;
    for (std::uint64_t e = graph.row_ptr[u]; e < graph.row_ptr[u + 1]; ++e)
      if (depth[graph.col[e]] < 0)
      {
        depth[graph.col[e]] = depth[u] + 1;
        out.push_back (graph.col[e]);
      }
  }
  return out;
}

/** Whether `ring` holds the same vertices as `want`, in any order. */
bool
sameVertices (std::vector<VertexIndex> ring, std::vector<VertexIndex> want)
{
  std::sort (ring.begin (), ring.end ());
  std::sort (want.begin (), want.end ());
  return ring == want;
}

/** The covariance of the ring's points, summed directly. */
Eigen::Matrix3d
directCovariance (const Signal3 &x, const std::vector<VertexIndex> &ring)
{
  Eigen::Vector3d mean = Eigen::Vector3d::Zero ();
  for (const VertexIndex j : ring)
    mean += x.row (j).transpose ();
  mean /= double (ring.size ());
  Eigen::Matrix3d c = Eigen::Matrix3d::Zero ();
  for (const VertexIndex j : ring)
  {
    const Eigen::Vector3d d = x.row (j).transpose () - mean;
    c += d * d.transpose ();
  }
  return c / double (ring.size ());
}

} // namespace

TEST (TwoRing, CollectsTheTwoRingsAndGrowsTheThirdEachVertexOnce)
{
  Signal3 x;
  const PointGraph graph = ringGraph (x);
  TwoRing two_ring;
  std::vector<VertexIndex> ring;
  for (VertexIndex v = 0; v < graph.numVertices (); v += 7)
  {
    two_ring.collect (graph, v, ring);
    ASSERT_EQ (ring.front (), v);
    EXPECT_TRUE (sameVertices (ring, within (graph, v, 2))) << "vertex " << v;
    const std::vector<VertexIndex> two = ring;
    two_ring.grow (graph, ring);
    // Grown by appending: the two rings stay in front, in their order.
    ASSERT_GE (ring.size (), two.size ());
    EXPECT_TRUE (std::equal (two.begin (), two.end (), ring.begin ())) << "vertex " << v;
    EXPECT_TRUE (sameVertices (ring, within (graph, v, 3))) << "vertex " << v;
  }
}

/** A k-NN graph of `n` seeded random points on a noisy sheet. */
PointGraph
sheetGraph (std::size_t n, int k)
{
  std::mt19937 rng (11);
  std::uniform_real_distribution<float> u (-1.0f, 1.0f);
  std::normal_distribution<float> g (0.0f, 0.01f);
  PointMatrix p (static_cast<Eigen::Index> (n), 3);
  for (Eigen::Index r = 0; r < p.rows (); ++r)
    p.row (r) << u (rng), u (rng), g (rng);
  KnnGraphParams params;
  params.k = k;
  return buildKnnGraph (p, params);
}

/** The stored entries TwoRing::collect scans for v's two rings (its bound). */
std::uint64_t
twoRingScan (const PointGraph &graph, VertexIndex v)
{
  std::uint64_t bound = 1;
  for (std::uint64_t e = graph.row_ptr[v]; e < graph.row_ptr[v + 1]; ++e)
    bound += 1 + (graph.row_ptr[graph.col[e] + 1] - graph.row_ptr[graph.col[e]]);
  return bound;
}

TEST (TwoRing, KNearestGraphsUpToSixtyNeighboursKeepTheirFullRings)
{
  const PointGraph graph = sheetGraph (3000, 60);
  TwoRing two_ring;
  std::vector<VertexIndex> ring;
  for (VertexIndex v = 0; v < graph.numVertices (); v += 97)
  {
    two_ring.collect (graph, v, ring);
    EXPECT_TRUE (sameVertices (ring, within (graph, v, 2))) << "vertex " << v;
    EXPECT_TRUE (two_ring.grow (graph, ring)) << "vertex " << v;
    EXPECT_TRUE (sameVertices (ring, within (graph, v, 3))) << "vertex " << v;
  }
}

TEST (TwoRing, TheDirectWindowAndTheHashSetCollectTheSameRings)
{
  // Vertices visited out of order, so that the window moves back and forth; windows from
  // one vertex (every other vertex in the hash set) to the whole graph give the same
  // rings, in the same order (first met).
  const PointGraph graph = sheetGraph (3000, 10);
  const std::size_t n = graph.numVertices ();
  TwoRing whole;  // the default window covers these 3,000 vertices
  std::vector<VertexIndex> want, ring;
  for (const std::size_t window : {std::size_t (1), std::size_t (2), std::size_t (64), std::size_t (1000)})
  {
    TwoRing two_ring (window);
    for (std::size_t step = 0; step < 300; ++step)
    {
      const auto v = static_cast<VertexIndex> ((step * 7919) % n);
      whole.collect (graph, v, want);
      two_ring.collect (graph, v, ring);
      ASSERT_EQ (ring, want) << "window " << window << ", vertex " << v;
      EXPECT_TRUE (sameVertices (ring, within (graph, v, 2))) << "window " << window << ", vertex " << v;
      ASSERT_TRUE (whole.grow (graph, want));
      ASSERT_TRUE (two_ring.grow (graph, ring));
      ASSERT_EQ (ring, want) << "window " << window << ", vertex " << v;
      EXPECT_TRUE (sameVertices (ring, within (graph, v, 3))) << "window " << window << ", vertex " << v;
    }
  }
}

TEST (TwoRing, ADenseGraphsRingIsTheOneRingAndDoesNotGrow)
{
  // k = 300 of 1,500 points: a row is below TwoRing::kMaxOneRing, but its two rings
  // would scan more than kScanLimit entries, so the ring is the vertex and its neighbours.
  const PointGraph graph = sheetGraph (1500, 300);
  TwoRing two_ring;
  std::vector<VertexIndex> ring;
  for (VertexIndex v = 0; v < graph.numVertices (); v += 101)
  {
    ASSERT_LE (graph.row_ptr[v + 1] - graph.row_ptr[v], TwoRing::kMaxOneRing);
    ASSERT_GT (twoRingScan (graph, v), TwoRing::kScanLimit);
    two_ring.collect (graph, v, ring);
    ASSERT_EQ (ring.front (), v);
    EXPECT_TRUE (sameVertices (ring, within (graph, v, 1))) << "vertex " << v;
    const std::vector<VertexIndex> one = ring;
    EXPECT_FALSE (two_ring.grow (graph, ring));
    EXPECT_EQ (ring, one);
  }
}

TEST (TwoRing, AVertexWithMoreNeighboursThanTheLimitKeepsTheNearest)
{
  // k >= N: every point linked to all others (1,299 neighbours each).
  const PointGraph graph = sheetGraph (1300, 5000);
  TwoRing two_ring;
  std::vector<VertexIndex> ring;
  for (VertexIndex v = 0; v < graph.numVertices (); v += 89)
  {
    ASSERT_EQ (graph.row_ptr[v + 1] - graph.row_ptr[v], graph.numVertices () - 1);
    // The kMaxOneRing largest weights of the row, ties by vertex number.
    std::vector<std::pair<float, VertexIndex>> row;
    for (std::uint64_t e = graph.row_ptr[v]; e < graph.row_ptr[v + 1]; ++e)
      row.emplace_back (-graph.weight[e], graph.col[e]);
    std::sort (row.begin (), row.end ());
    std::vector<VertexIndex> want{v};
    for (std::size_t r = 0; r < TwoRing::kMaxOneRing; ++r)
      want.push_back (row[r].second);
    two_ring.collect (graph, v, ring);
    ASSERT_EQ (ring.front (), v);
    EXPECT_EQ (ring.size (), TwoRing::kMaxOneRing + 1);
    EXPECT_TRUE (sameVertices (ring, want)) << "vertex " << v;
    EXPECT_FALSE (two_ring.grow (graph, ring));
    EXPECT_EQ (ring.size (), TwoRing::kMaxOneRing + 1);
  }
}

TEST (RingMoments, AGrownRingsCovarianceIsTheWholeRingsToTheBit)
{
  Signal3 x;
  const PointGraph graph = ringGraph (x);
  TwoRing two_ring;
  std::vector<VertexIndex> ring;
  for (VertexIndex v = 0; v < graph.numVertices (); v += 11)
  {
    two_ring.collect (graph, v, ring);
    RingMoments moments (v);
    const std::vector<VertexIndex> two = ring;
    const Eigen::Matrix3d narrow = moments.covariance (x, ring);
    EXPECT_TRUE (narrow.isApprox (directCovariance (x, ring), 1e-12)) << "vertex " << v;
    two_ring.grow (graph, ring);
    const Eigen::Matrix3d wide = moments.covariance (x, ring);
    EXPECT_EQ (wide, ringCovariance (x, ring, v)) << "vertex " << v;  // to the bit
    EXPECT_TRUE (wide.isApprox (directCovariance (x, ring), 1e-12)) << "vertex " << v;
    // A shorter ring afterwards is summed afresh, not taken from the longer one's sums.
    EXPECT_EQ (moments.covariance (x, two), ringCovariance (x, two, v)) << "vertex " << v;
  }
}

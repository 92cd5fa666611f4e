/*
 * pcl_graph_denoise: graph-signal-processing point cloud denoising for PCL.
 * SPDX-License-Identifier: BSD-3-Clause
 *
 * Graph construction and outlier removal against PCL's own tools, measured in the
 * same run on the same points. Prints figures; asserts nothing.
 *
 *   bench_graph [sizes...]        (default: 100000 1000000)
 *
 * 1. k-NN graph (k = 10, weights and symmetrisation included, all threads) versus a
 *    plain single-threaded loop of pcl::KdTreeFLANN::nearestKSearch over the same
 *    points in their given (random) order; and the search alone, Morton-ordered, on
 *    all threads, with nanoflann (the core's choice) and with KdTreeFLANN. Every time
 *    is the median of 3 runs.
 * 2. Graph memory in bytes per point.
 * 3. Outlier removal on a noisy sphere with 5% uniform outliers in its bounding box:
 *    GraphDegreeOutlierRemoval (defaults) versus pcl::StatisticalOutlierRemoval (mean K
 *    50, multiplier 1.0) and pcl::RadiusOutlierRemoval (at least 2 neighbours within
 *    1.5, 2 and 3 times the point spacing our filter derived): time, precision,
 *    recall, F1; and the ceiling no filter can pass: the best F1 of an oracle that
 *    knows the true sphere (outliers inside the noisy shell look like surface points).
 */
#include <pcl_graph_denoise/core/graph.h>
#include <pcl_graph_denoise/graph_degree_outlier_removal.h>

#include "point_counts.h"
#include "synthetic.h"
#include "timing.h"

#include <pcl/filters/radius_outlier_removal.h>
#include <pcl/filters/statistical_outlier_removal.h>
#include <pcl/kdtree/kdtree_flann.h>

#define NANOFLANN_FIRST_MATCH
#include <nanoflann.hpp>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstdio>
#include <cmath>
#include <cstdlib>
#include <string>
#include <thread>
#include <utility>
#include <vector>

using namespace pcl_graph_denoise;
using Cloud = pcl::PointCloud<pcl::PointXYZ>;

namespace {

using synthetic::toMatrix;

/** Each timing of the graph section is the median of this many runs. */
constexpr int kRepeats = 3;

/** Runs body(i) for i in [0, n) on `threads` threads, blocks of 1024. */
template <typename Body>
void
parallel (std::size_t n, int threads, Body body)
{
  std::atomic<std::size_t> next (0);
  auto work = [&] () {
    for (std::size_t b = next.fetch_add (1024); b < n; b = next.fetch_add (1024))
      for (std::size_t i = b; i < std::min (n, b + 1024); ++i)
        body (i);
  };
  std::vector<std::thread> pool;
  for (int t = 1; t < threads; ++t)
    pool.emplace_back (work);
  work ();
  for (auto &t : pool)
    t.join ();
}

struct MatrixDataset
{
  const core::PointMatrix &m;
  std::size_t kdtree_get_point_count () const { return m.rows (); }
  float kdtree_get_pt (std::size_t i, std::size_t d) const { return m (i, d); }
  template <typename B>
  bool kdtree_get_bbox (B &) const { return false; }
};

void
benchGraph (std::size_t n, int threads)
{
  const Cloud::Ptr cloud (new Cloud (synthetic::noisySphere (n, 1.0, 0.01, 7)));
  const int k = 10;
  std::printf ("\n== k-NN graph, noisy unit sphere (sigma 0.01), %zu points, k = %d, %d threads "
               "(each time the median of %d runs)\n",
               n, k, threads, kRepeats);

  // PCL's single-threaded loop in the given (random) order.
  pcl::KdTreeFLANN<pcl::PointXYZ> flann;
  const double t_flann_build = medianSeconds (kRepeats, [&] { flann.setInputCloud (cloud); });
  pcl::Indices idx (k + 1);
  std::vector<float> d2 (k + 1);
  const double t_flann_loop = medianSeconds (kRepeats, [&] {
    for (std::size_t i = 0; i < n; ++i)
      flann.nearestKSearch ((*cloud)[i], k + 1, idx, d2);
  });

  // Ours, everything included; the previous run's graph is released before each run (the
  // loop above writes into buffers it reuses).
  const core::PointMatrix points = toMatrix (*cloud);
  core::KnnGraphParams params;
  params.k = k;
  params.num_threads = threads;
  core::PointGraph graph;
  const double t_graph =
      medianSeconds (kRepeats, [&] { graph = core::PointGraph (); },
                     [&] { graph = core::buildKnnGraph (points, params); });

  // The search alone on Morton-ordered points, with either library.
  core::PointMatrix ordered (n, 3);
  for (std::size_t v = 0; v < n; ++v)
    ordered.row (v) = points.row (graph.order[v]);
  Cloud::Ptr ordered_cloud (new Cloud);
  for (std::size_t v = 0; v < n; ++v)
    ordered_cloud->push_back (pcl::PointXYZ (ordered (v, 0), ordered (v, 1), ordered (v, 2)));
  pcl::KdTreeFLANN<pcl::PointXYZ> flann_ordered;
  const double t_fo_build =
      medianSeconds (kRepeats, [&] { flann_ordered.setInputCloud (ordered_cloud); });
  const double t_fo_search = medianSeconds (kRepeats, [&] {
    parallel (n, threads, [&] (std::size_t i) {
      thread_local pcl::Indices ti (k + 1);
      thread_local std::vector<float> td (k + 1);
      flann_ordered.nearestKSearch ((*ordered_cloud)[i], k + 1, ti, td);
    });
  });
  MatrixDataset data{ordered};
  using Tree = nanoflann::KDTreeSingleIndexAdaptor<
      nanoflann::L2_Simple_Adaptor<float, MatrixDataset, float, std::uint32_t>, MatrixDataset,
      3, std::uint32_t>;
  std::unique_ptr<Tree> nano;
  const double t_nano_build = medianSeconds (kRepeats, [&] {
    nano.reset (new Tree (3, data, nanoflann::KDTreeSingleIndexAdaptorParams (16)));
  });
  const double t_nano_search = medianSeconds (kRepeats, [&] {
    parallel (n, threads, [&] (std::size_t i) {
      std::uint32_t ti[16];
      float td[16];
      nano->knnSearch (ordered.row (i).data (), k + 1, ti, td);
    });
  });

  std::printf ("  PCL KdTreeFLANN, 1 thread, given order: build %.3f s + loop of nearestKSearch "
               "%.3f s\n",
               t_flann_build, t_flann_loop);
  std::printf ("  ours: buildKnnGraph (Morton order, search, symmetrise, weights) %.3f s  = %.3fx "
               "the loop, %.3fx build + loop\n",
               t_graph, t_graph / t_flann_loop, t_graph / (t_flann_build + t_flann_loop));
  std::printf ("  search alone, Morton order, %d threads: nanoflann build %.3f + search %.3f s; "
               "KdTreeFLANN build %.3f + search %.3f s\n",
               threads, t_nano_build, t_nano_search, t_fo_build, t_fo_search);
  std::printf ("  graph: %.2f stored entries per point (%.2f edges), memory %.1f bytes per point "
               "(CSR offsets, 32-bit neighbours, float weights, order)\n",
               double (graph.numEntries ()) / n, double (graph.numEdges ()) / n,
               double (graph.memoryBytes ()) / n);
}

struct Score
{
  double precision, recall, f1;
};

Score
score (const pcl::Indices &removed, const std::vector<bool> &truth)
{
  std::size_t tp = 0, positives = 0;
  for (auto i : removed)
    tp += truth[i];
  for (bool t : truth)
    positives += t;
  Score s;
  s.precision = removed.empty () ? 1.0 : double (tp) / removed.size ();
  s.recall = positives == 0 ? 1.0 : double (tp) / positives;
  s.f1 = s.precision + s.recall > 0 ? 2 * s.precision * s.recall / (s.precision + s.recall) : 0;
  return s;
}

/** The best F1 any filter can reach on points of a noisy unit sphere at the origin with
 *  uniform outliers: outliers that land inside the noisy shell are indistinguishable from
 *  surface points, so the best rule removes the points farther than some distance from
 *  the true sphere. Sweeps that distance and keeps the best F1. */
Score
oracleScore (const Cloud &cloud, const std::vector<bool> &truth)
{
  std::vector<std::pair<float, bool>> by_distance (cloud.size ());
  std::size_t positives = 0;
  for (std::size_t i = 0; i < cloud.size (); ++i)
  {
    by_distance[i] = {std::abs (cloud[i].getVector3fMap ().norm () - 1.0f), truth[i]};
    positives += truth[i];
  }
  // Farthest first: removing the first m points, for every m.
  std::sort (by_distance.begin (), by_distance.end (),
             [] (const auto &a, const auto &b) { return a.first > b.first; });
  Score best{1.0, 0.0, 0.0};
  std::size_t tp = 0;
  for (std::size_t m = 1; m <= by_distance.size (); ++m)
  {
    tp += by_distance[m - 1].second;
    const double precision = double (tp) / m, recall = double (tp) / positives;
    const double f1 = tp ? 2 * precision * recall / (precision + recall) : 0.0;
    if (f1 > best.f1)
      best = {precision, recall, f1};
  }
  return best;
}

void
benchOutliers (std::size_t n, double noise, int threads)
{
  Cloud::Ptr cloud (new Cloud (synthetic::noisySphere (n, 1.0, noise, 11)));
  const std::vector<bool> truth = synthetic::addUniformOutliers (*cloud, 0.05, 0.0, 12);
  std::printf ("\n== outliers: noisy unit sphere (sigma %.3f), %zu points + 5%% uniform outliers "
               "in the bounding box (%zu points)\n",
               noise, n, cloud->size ());
  std::printf ("  %-44s %8s %9s %9s %9s\n", "method", "time s", "precision", "recall", "F1");

  GraphDegreeOutlierRemoval<pcl::PointXYZ> ours (true);
  ours.setInputCloud (cloud);
  ours.setNumberOfThreads (threads);
  pcl::Indices kept;
  const double t_ours = seconds ([&] { ours.filter (kept); });
  const Score s_ours = score (*ours.getRemovedIndices (), truth);
  std::printf ("  %-44s %8.3f %9.4f %9.4f %9.4f\n", "GraphDegreeOutlierRemoval (defaults)", t_ours,
               s_ours.precision, s_ours.recall, s_ours.f1);

  pcl::StatisticalOutlierRemoval<pcl::PointXYZ> sor (true);
  sor.setInputCloud (cloud);
  sor.setMeanK (50);
  sor.setStddevMulThresh (1.0);
  const double t_sor = seconds ([&] { sor.filter (kept); });
  const Score s_sor = score (*sor.getRemovedIndices (), truth);
  std::printf ("  %-44s %8.3f %9.4f %9.4f %9.4f\n", "pcl::StatisticalOutlierRemoval (50, 1.0)", t_sor,
               s_sor.precision, s_sor.recall, s_sor.f1);

  // RadiusOutlierRemoval at several radii, multiples of the spacing our filter derived
  // (its epsilon is 3 spacings), so that it is shown at its best.
  const double spacing = ours.getUsedRadius () / 3.0;
  double best_ror_f1 = 0.0, best_ror_time = 0.0;
  for (double factor : {1.5, 2.0, 3.0})
  {
    pcl::RadiusOutlierRemoval<pcl::PointXYZ> ror (true);
    ror.setInputCloud (cloud);
    ror.setRadiusSearch (factor * spacing);
    ror.setMinNeighborsInRadius (2);
    const double t_ror = seconds ([&] { ror.filter (kept); });
    const Score s_ror = score (*ror.getRemovedIndices (), truth);
    char label[96];
    std::snprintf (label, sizeof (label), "pcl::RadiusOutlierRemoval (r %.4f, min 2)",
                   factor * spacing);
    std::printf ("  %-44s %8.3f %9.4f %9.4f %9.4f\n", label, t_ror, s_ror.precision,
                 s_ror.recall, s_ror.f1);
    if (s_ror.f1 > best_ror_f1)
      best_ror_f1 = s_ror.f1, best_ror_time = t_ror;
  }
  std::printf ("  ours vs SOR: %.2fx the time, F1 %+.4f; vs the best ROR: %.2fx the time, F1 "
               "%+.4f\n",
               t_ours / t_sor, s_ours.f1 - s_sor.f1, t_ours / best_ror_time,
               s_ours.f1 - best_ror_f1);
  const Score ceiling = oracleScore (*cloud, truth);
  std::printf ("  ceiling: an oracle that knows the sphere and removes every point farther than "
               "the best distance from it: precision %.4f, recall %.4f, F1 %.4f (ours %+.4f)\n",
               ceiling.precision, ceiling.recall, ceiling.f1, s_ours.f1 - ceiling.f1);
}

} // namespace

int
main (int argc, char **argv)
{
  std::setvbuf (stdout, nullptr, _IOLBF, 0);  // progress shows as it comes
  const std::vector<std::size_t> sizes = pointCounts (argc, argv, {100000, 1000000});
  if (sizes.empty ())
    return 2;
  const int threads = std::max (1u, std::thread::hardware_concurrency ());
  for (std::size_t n : sizes)
    benchGraph (n, threads);
  for (std::size_t n : sizes)
    for (double noise : {0.002, 0.005})
      benchOutliers (n, noise, threads);
  return 0;
}

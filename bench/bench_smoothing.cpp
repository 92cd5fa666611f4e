/*
 * pcl_graph_denoise: graph-signal-processing point cloud denoising for PCL.
 * SPDX-License-Identifier: BSD-3-Clause
 *
 * Smoothing speed and accuracy against the peers, measured in the same run on the same
 * points. Prints figures; asserts nothing.
 *
 *   bench_smoothing [sizes...]      (default: 100000 1000000)
 *
 * For a noisy unit sphere and a noisy cube [-1,1]^3 (Gaussian noise 0.01) of each size:
 * time and mean distance to the true surface of GraphTikhonovSmoothing and
 * GraphTVSmoothing (defaults, with setAdaptiveSupport (false), with a quadric at every
 * vertex (setPatchCover (0)), and with the risk-estimate gamma), pcl::MovingLeastSquares (polynomial order 2, all threads, at search radii of
 * 1, 1.5, 2 and 3 times the mean distance to the 20th neighbour, so that its best radius
 * is shown), and CGAL::jet_smooth_point_set (k = 18, parallel).
 * Also: the time to build the k-NN graph alone (the median of three builds), the ratios
 * the targets are stated in,
 * and how far the default gamma is from the best gamma of a sweep (0.25x to 4x the
 * default).
 */
#include <pcl_graph_denoise/core/graph.h>
#include <pcl_graph_denoise/graph_tikhonov_smoothing.h>
#include <pcl_graph_denoise/graph_tv_smoothing.h>

#include "point_counts.h"
#include "synthetic.h"
#include "timing.h"

#include "peers.h"

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <functional>
#include <thread>
#include <vector>

using namespace pcl_graph_denoise;
using Cloud = pcl::PointCloud<pcl::PointXYZ>;

namespace {

using synthetic::meanDistance;
using Distance = synthetic::SurfaceDistance;

void
row (const char *method, double time, double error, double input_error)
{
  std::printf ("  %-46s %8.3f %10.5f %8.2fx\n", method, time, error, input_error / error);
}

template <typename Filter>
double
sweepRow (const char *name, const Cloud::Ptr &cloud, const Distance &distance)
{
  Filter filter;
  filter.setInputCloud (cloud);
  Cloud out;
  filter.filter (out);
  const double default_gamma = filter.getUsedGamma ();
  const double default_error = meanDistance (out, distance);
  double best_error = default_error, best_factor = 1.0;
  std::printf ("  %-12s gamma sweep (x default %.4g):", name, default_gamma);
  for (double factor : {0.25, 0.5, 1.0, 2.0, 4.0})
  {
    filter.setGamma (factor * default_gamma);
    filter.filter (out);
    const double error = meanDistance (out, distance);
    std::printf (" %.2fx %.5f", factor, error);
    if (error < best_error)
      best_error = error, best_factor = factor;
  }
  std::printf ("\n  %-12s best at %.2fx the default; the default's error is %.3fx the best\n", name,
               best_factor, default_error / best_error);
  return default_error / best_error;
}

void
benchShape (const char *shape, const Cloud::Ptr &cloud, const Distance &distance)
{
  const int threads = std::max (1u, std::thread::hardware_concurrency ());
  const double input_error = meanDistance (*cloud, distance);
  std::printf ("\n== %s, %zu points, noise 0.01, %d threads; input mean distance %.5f\n", shape,
               cloud->size (), threads, input_error);
  std::printf ("  %-46s %8s %10s %9s\n", "method", "time s", "distance", "reduction");

  core::PointMatrix points (cloud->size (), 3);
  for (std::size_t i = 0; i < cloud->size (); ++i)
    points.row (i) = (*cloud)[i].getVector3fMap ().transpose ();
  // The ratios' denominator: the median of three builds (the first build of a process
  // can take half as long again, which flattered the ratios).
  const double t_graph = medianSeconds (3, [] {}, [&] { core::buildKnnGraph (points); });

  Cloud out;
  GraphTikhonovSmoothing<pcl::PointXYZ> tikhonov;
  tikhonov.setInputCloud (cloud);
  const double t_tik = seconds ([&] { tikhonov.filter (out); });
  row ("GraphTikhonovSmoothing (defaults)", t_tik, meanDistance (out, distance), input_error);
  GraphTVSmoothing<pcl::PointXYZ> tv;
  tv.setInputCloud (cloud);
  const double t_tv = seconds ([&] { tv.filter (out); });
  row ("GraphTVSmoothing (defaults)", t_tv, meanDistance (out, distance), input_error);
  // The quadrics over two graph rings everywhere (not the adaptive support).
  tikhonov.setAdaptiveSupport (false);
  const double t_tik_two_rings = seconds ([&] { tikhonov.filter (out); });
  row ("GraphTikhonovSmoothing (-adaptive_support 0)", t_tik_two_rings, meanDistance (out, distance),
       input_error);
  tikhonov.setAdaptiveSupport (true);
  tv.setAdaptiveSupport (false);
  const double t_tv_two_rings = seconds ([&] { tv.filter (out); });
  row ("GraphTVSmoothing (-adaptive_support 0)", t_tv_two_rings, meanDistance (out, distance), input_error);
  tv.setAdaptiveSupport (true);
  // A quadric at every vertex instead of at the default cover's centres.
  const int cover = tikhonov.getPatchCover ();
  tikhonov.setPatchCover (0);
  const double t_tik_every = seconds ([&] { tikhonov.filter (out); });
  row ("GraphTikhonovSmoothing (-patch_cover 0)", t_tik_every, meanDistance (out, distance), input_error);
  tikhonov.setPatchCover (cover);
  tv.setPatchCover (0);
  const double t_tv_every = seconds ([&] { tv.filter (out); });
  row ("GraphTVSmoothing (-patch_cover 0)", t_tv_every, meanDistance (out, distance), input_error);
  tv.setPatchCover (cover);
  // The risk-estimate selection of gamma (four blocks of 12,500 points above 50,000).
  tikhonov.setGammaSelection (GammaSelection::RISK_ESTIMATE);
  const double t_tik_risk = seconds ([&] { tikhonov.filter (out); });
  row ("GraphTikhonovSmoothing (-gamma risk)", t_tik_risk, meanDistance (out, distance), input_error);
  tikhonov.setGammaSelection (GammaSelection::RULE);
  tv.setGammaSelection (GammaSelection::RISK_ESTIMATE);
  const double t_tv_risk = seconds ([&] { tv.filter (out); });
  row ("GraphTVSmoothing (-gamma risk)", t_tv_risk, meanDistance (out, distance), input_error);
  tv.setGammaSelection (GammaSelection::RULE);

  const double spacing20 = peers::meanKthNeighbourDistance (*cloud, 20);
  double best_mls_error = 1e300, best_mls_time = 0.0;
  for (double factor : {1.0, 1.5, 2.0, 3.0})
  {
    const double t = seconds ([&] { out = peers::movingLeastSquares (*cloud, factor * spacing20); });
    const double error = meanDistance (out, distance);
    char label[96];
    std::snprintf (label, sizeof (label), "pcl::MovingLeastSquares (order 2, r = %.1f d20)", factor);
    row (label, t, error, input_error);
    if (error < best_mls_error)
      best_mls_error = error, best_mls_time = t;
  }

  Cloud jet;
  const double t_jet = seconds ([&] { jet = peers::jetSmooth (*cloud, 18); });
  const double jet_error = meanDistance (jet, distance);
  row ("CGAL::jet_smooth_point_set (k = 18)", t_jet, jet_error, input_error);

  std::printf ("  k-NN graph alone %.3f s; Tikhonov %.2fx the graph build (target <= 2), TV "
               "%.2fx (target <= 6)\n",
               t_graph, t_tik / t_graph, t_tv / t_graph);
  std::printf ("  with -adaptive_support 0: Tikhonov %.2fx the graph build, TV %.2fx\n",
               t_tik_two_rings / t_graph, t_tv_two_rings / t_graph);
  std::printf ("  with -patch_cover 0: Tikhonov %.2fx the graph build (the default cover %d takes "
               "%.2fx its time), TV %.2fx (%.2fx)\n",
               t_tik_every / t_graph, cover, t_tik / t_tik_every, t_tv_every / t_graph, t_tv / t_tv_every);
  std::printf ("  with -gamma risk: Tikhonov %.2fx the graph build (%.2fx its default's time), TV %.2fx "
               "(%.2fx)\n",
               t_tik_risk / t_graph, t_tik_risk / t_tik, t_tv_risk / t_graph, t_tv_risk / t_tv);
  std::printf ("  time against MLS at its most accurate radius: Tikhonov %.2fx, TV %.2fx",
               t_tik / best_mls_time, t_tv / best_mls_time);
  std::printf ("; against jet smoothing: Tikhonov %.2fx, TV %.2fx\n", t_tik / t_jet, t_tv / t_jet);
  sweepRow<GraphTikhonovSmoothing<pcl::PointXYZ>> ("Tikhonov", cloud, distance);
  sweepRow<GraphTVSmoothing<pcl::PointXYZ>> ("TV", cloud, distance);
}

} // namespace

int
main (int argc, char **argv)
{
  std::setvbuf (stdout, nullptr, _IOLBF, 0);  // progress shows as it comes
  const std::vector<std::size_t> sizes = pointCounts (argc, argv, {100000, 1000000});
  if (sizes.empty ())
    return 2;
  const Distance to_sphere = synthetic::distanceToUnitSphere;
  const Distance to_cube = synthetic::distanceToCube;
  for (std::size_t n : sizes)
  {
    benchShape ("noisy unit sphere", Cloud::Ptr (new Cloud (synthetic::noisySphere (n, 1.0, 0.01, 41))),
                to_sphere);
    benchShape ("noisy cube [-1,1]^3", Cloud::Ptr (new Cloud (synthetic::noisyCube (n, 0.01, 42))),
                to_cube);
  }
  return 0;
}

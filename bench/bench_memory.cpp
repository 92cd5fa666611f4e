/*
 * pcl_graph_denoise: graph-signal-processing point cloud denoising for PCL.
 * SPDX-License-Identifier: BSD-3-Clause
 *
 * Peak memory of the filters and of PCL's own chain on the same cloud, in bytes per
 * input point, next to the estimate the filters check against their memory limit
 * (setMemoryLimit). Prints figures; asserts nothing.
 *
 *   bench_memory [sizes...]        (default: 1000000)
 *
 * The cloud: a noisy unit sphere (noise 1% of the radius) with 5% uniform outliers in its
 * bounding box. Each job runs in a child process (fork) that resets its high-water mark
 * (/proc/self/clear_refs) once the input is in memory; its peak is the high-water mark
 * (VmHWM) less the resident size at that moment, so the input cloud itself is not
 * counted, the output is. Jobs:
 *   outliers         GraphDegreeOutlierRemoval, defaults
 *   tikhonov, tv     GraphTikhonovSmoothing, GraphTVSmoothing, defaults
 *   chain            outliers then TV (a filter chain: the kept cloud, then its smoothing)
 *   pcl chain        pcl::StatisticalOutlierRemoval (mean K 50, multiplier 1) then
 *                    pcl::MovingLeastSquares (order 2, radius 2 x the mean 20-NN distance)
 *   jet              CGAL::jet_smooth_point_set (k = 18)
 */
#include <pcl_graph_denoise/graph_degree_outlier_removal.h>
#include <pcl_graph_denoise/graph_tikhonov_smoothing.h>
#include <pcl_graph_denoise/graph_tv_smoothing.h>

#include "peak_memory.h"
#include "peers.h"
#include "point_counts.h"
#include "synthetic.h"

#include <pcl/filters/statistical_outlier_removal.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

using namespace pcl_graph_denoise;
using Cloud = pcl::PointCloud<pcl::PointXYZ>;

namespace {

using synthetic::PeakMemory;

void
row (const char *label, const PeakMemory &m, std::size_t n, double peer_bytes)
{
  std::printf ("  %-58s %8.1f MB  %7.1f bytes/point  %6.2f s", label, m.bytes / 1e6,
               m.bytes / double (n), m.seconds);
  if (peer_bytes > 0.0)
    std::printf ("  %5.2fx the PCL chain", m.bytes / peer_bytes);
  if (m.returned > 0)
    std::printf ("  (estimate %.1f bytes/point, %.2fx the peak)", double (m.returned) / double (n),
                 double (m.returned) / m.bytes);
  std::printf ("\n");
}

void
run (std::size_t n)
{
  Cloud::Ptr cloud (new Cloud (synthetic::noisySphere (n, 1.0, 0.01, 7)));
  synthetic::addUniformOutliers (*cloud, 0.05, 0.1, 8);
  const std::size_t total = cloud->size ();
  std::printf ("noisy sphere, %zu points + 5%% outliers = %zu points (input cloud %.1f MB, "
               "not counted)\n",
               n, total, double (total * sizeof (pcl::PointXYZ)) / 1e6);

  const PeakMemory pcl_chain = synthetic::measurePeakMemory ([&] {
    pcl::StatisticalOutlierRemoval<pcl::PointXYZ> sor;
    sor.setInputCloud (cloud);
    sor.setMeanK (50);
    sor.setStddevMulThresh (1.0);
    Cloud::Ptr kept (new Cloud);
    sor.filter (*kept);
    const double radius = 2.0 * peers::meanKthNeighbourDistance (*kept, 20);
    const Cloud out = peers::movingLeastSquares (*kept, radius);
    return std::size_t (out.empty () ? 0 : 0);
  });
  const PeakMemory outliers = synthetic::measurePeakMemory ([&] {
    GraphDegreeOutlierRemoval<pcl::PointXYZ> filter;
    filter.setInputCloud (cloud);
    Cloud out;
    filter.filter (out);
    return filter.estimateMemory (cloud->size ());
  });
  const PeakMemory tikhonov = synthetic::measurePeakMemory ([&] {
    GraphTikhonovSmoothing<pcl::PointXYZ> filter;
    filter.setInputCloud (cloud);
    Cloud out;
    filter.filter (out);
    return filter.estimateMemory (cloud->size ());
  });
  const PeakMemory tv = synthetic::measurePeakMemory ([&] {
    GraphTVSmoothing<pcl::PointXYZ> filter;
    filter.setInputCloud (cloud);
    Cloud out;
    filter.filter (out);
    return filter.estimateMemory (cloud->size ());
  });
  const PeakMemory chain = synthetic::measurePeakMemory ([&] {
    GraphDegreeOutlierRemoval<pcl::PointXYZ> outlier_filter;
    outlier_filter.setInputCloud (cloud);
    Cloud::Ptr kept (new Cloud);
    outlier_filter.filter (*kept);
    GraphTVSmoothing<pcl::PointXYZ> tv_filter;
    tv_filter.setInputCloud (kept);
    Cloud out;
    tv_filter.filter (out);
    return std::max (outlier_filter.estimateMemory (cloud->size ()),
                     kept->size () * sizeof (pcl::PointXYZ) + tv_filter.estimateMemory (kept->size ()));
  });
  const PeakMemory jet = synthetic::measurePeakMemory ([&] {
    const Cloud out = peers::jetSmooth (*cloud, 18);
    return std::size_t (out.empty () ? 0 : 0);
  });

  const double peer = pcl_chain.bytes;
  row ("GraphDegreeOutlierRemoval (defaults)", outliers, total, peer);
  row ("GraphTikhonovSmoothing (defaults)", tikhonov, total, peer);
  row ("GraphTVSmoothing (defaults)", tv, total, peer);
  row ("chain: GraphDegreeOutlierRemoval -> GraphTVSmoothing", chain, total, peer);
  row ("PCL chain: StatisticalOutlierRemoval -> MovingLeastSquares", pcl_chain, total, 0.0);
  row ("CGAL::jet_smooth_point_set (k = 18)", jet, total, peer);
}

} // namespace

int
main (int argc, char **argv)
{
  const std::vector<std::size_t> sizes = pointCounts (argc, argv, {1000000});
  if (sizes.empty ())
    return 2;
  for (const std::size_t n : sizes)
    run (n);
  return 0;
}

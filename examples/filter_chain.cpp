/*
 * pcl_graph_denoise: graph-signal-processing point cloud denoising for PCL.
 * SPDX-License-Identifier: BSD-3-Clause
 *
 * The library in an ordinary PCL filter chain, written as a PCL user writes one:
 * pcl::VoxelGrid -> GraphDegreeOutlierRemoval -> GraphTVSmoothing, every stage held
 * through a pcl::Filter<PointT>::Ptr and run in turn. The point type carries colour,
 * which the graph filters keep (only x, y, z of the smoothed points change).
 *
 *   pcl_graph_denoise_filter_chain [input.pcd [output.pcd]]
 *
 * Without an input it uses the demo's generated table scene, coloured by height, and
 * also prints the error to the true scene before and after.
 */
#include <pcl_graph_denoise/graph_degree_outlier_removal.h>
#include <pcl_graph_denoise/graph_tv_smoothing.h>

#include "synthetic.h"

#include <pcl/filters/voxel_grid.h>
#include <pcl/io/pcd_io.h>
#include <pcl/common/io.h>
#include <pcl/point_types.h>

#include <algorithm>
#include <cstdint>
#include <cstdio>
#include <memory>
#include <string>
#include <vector>

using PointT = pcl::PointXYZRGB;
using Cloud = pcl::PointCloud<PointT>;

int
main (int argc, char **argv)
{
  if (argc > 3 || (argc > 1 && (std::string (argv[1]) == "-h" || std::string (argv[1]) == "--help")))
  {
    std::printf ("usage: %s [input.pcd [output.pcd]]\n", argv[0]);
    return argc > 3 ? 1 : 0;
  }
  Cloud::Ptr cloud (new Cloud);
  const bool generated = argc < 2;
  if (generated)
  {
    const auto scene = pcl_graph_denoise::synthetic::demoScene (42);
    for (const auto &p : scene)
    {
      PointT q;
      q.x = p.x, q.y = p.y, q.z = p.z;
      const auto shade = static_cast<std::uint8_t> (std::min (255.0, std::max (0.0, 128.0 + 400.0 * p.z)));
      q.r = shade, q.g = 96, q.b = static_cast<std::uint8_t> (255 - shade);
      cloud->push_back (q);
    }
  }
  else if (pcl::io::loadPCDFile (argv[1], *cloud) < 0)
  {
    std::fprintf (stderr, "error: cannot read %s\n", argv[1]);
    return 1;
  }

  // The chain: each stage a pcl::Filter, configured once, run in turn.
  auto voxel = std::make_shared<pcl::VoxelGrid<PointT>> ();
  voxel->setLeafSize (0.002f, 0.002f, 0.002f);  // 2 mm: thins duplicates, keeps detail
  auto outliers = std::make_shared<pcl_graph_denoise::GraphDegreeOutlierRemoval<PointT>> ();
  auto smoothing = std::make_shared<pcl_graph_denoise::GraphTVSmoothing<PointT>> ();
  const std::vector<std::pair<std::string, pcl::Filter<PointT>::Ptr>> chain = {
      {"VoxelGrid", voxel}, {"GraphDegreeOutlierRemoval", outliers}, {"GraphTVSmoothing", smoothing}};

  const auto sceneError = [] (const Cloud &c) {
    pcl::PointCloud<pcl::PointXYZ> xyz;
    pcl::copyPointCloud (c, xyz);
    return 1000.0 * pcl_graph_denoise::synthetic::demoSceneError (xyz);
  };
  std::printf ("input: %zu points\n", cloud->size ());
  const double error_before = generated ? sceneError (*cloud) : 0.0;
  for (const auto &[name, filter] : chain)
  {
    Cloud::Ptr next (new Cloud);
    filter->setInputCloud (cloud);
    filter->filter (*next);
    std::printf ("%s: %zu -> %zu points\n", name.c_str (), cloud->size (), next->size ());
    if (next->empty ())
    {
      std::fprintf (stderr, "error: %s left no point\n", name.c_str ());
      return 1;
    }
    cloud = next;
  }
  if (generated)
    std::printf ("mean distance to the true scene: %.3f mm -> %.3f mm\n", error_before,
                 sceneError (*cloud));
  if (argc == 3 && pcl::io::savePCDFileBinary (argv[2], *cloud) < 0)
  {
    std::fprintf (stderr, "error: cannot write %s\n", argv[2]);
    return 1;
  }
  return 0;
}

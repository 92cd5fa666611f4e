/*
 * pcl_graph_denoise: graph-signal-processing point cloud denoising for PCL.
 * SPDX-License-Identifier: BSD-3-Clause
 *
 * Denoising the frames of a moving sensor: the chain a PCL user needs, since the
 * spatio-temporal graph links frames only where they share one coordinate system.
 *  1. register each frame onto the previous one with pcl::IterativeClosestPoint, coarse
 *     to fine on pcl::VoxelGrid-downsampled copies (leaf 1/200 of the extent, then 1/800),
 *     each pair started from the previous pair's motion, and chain the transforms into
 *     frame 0's coordinates;
 *  2. move every frame there (pcl::transformPointCloud) and stream the frames through
 *     GraphSequenceSmoothing (push / flush, as a live node would);
 *  3. move each denoised frame back into its own sensor coordinates and write it.
 *
 *   pcl_graph_denoise_sequence_registration OUT_DIR FRAME.pcd FRAME.pcd [FRAME.pcd...]
 *
 * It prints, for every pair, ICP's convergence and fitness, and the median distance of
 * a frame's points to the next frame's nearest point before and after registration;
 * it fails (exit 1) when a registration does not converge or does not bring the frames
 * closer. The results are OUT_DIR/<frame's file name>.
 */
#include <pcl_graph_denoise/graph_sequence_smoothing.h>

#include <pcl/common/common.h>
#include <pcl/common/time.h>
#include <pcl/common/transforms.h>
#include <pcl/filters/filter.h>
#include <pcl/filters/voxel_grid.h>
#include <pcl/io/pcd_io.h>
#include <pcl/kdtree/kdtree_flann.h>
#include <pcl/point_types.h>
#include <pcl/registration/icp.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <string>
#include <vector>

using PointT = pcl::PointXYZ;
using Cloud = pcl::PointCloud<PointT>;

namespace {

/** The finite points of a cloud on a voxel grid of the given leaf. */
Cloud::Ptr
downsample (const Cloud &cloud, float leaf)
{
  Cloud::Ptr finite (new Cloud), out (new Cloud);
  pcl::Indices kept;
  pcl::removeNaNFromPointCloud (cloud, *finite, kept);
  pcl::VoxelGrid<PointT> grid;
  grid.setInputCloud (finite);
  grid.setLeafSize (leaf, leaf, leaf);
  grid.filter (*out);
  return out;
}

/** Median distance of the points of `from` to their nearest point in `to`. */
double
medianGap (const Cloud::ConstPtr &from, const Cloud::ConstPtr &to)
{
  pcl::KdTreeFLANN<PointT> tree;
  tree.setInputCloud (to);
  std::vector<double> gap;
  pcl::Indices index (1);
  std::vector<float> d2 (1);
  for (const auto &p : *from)
    if (tree.nearestKSearch (p, 1, index, d2) == 1)
      gap.push_back (std::sqrt (d2[0]));
  if (gap.empty ())
    return 0.0;
  std::nth_element (gap.begin (), gap.begin () + gap.size () / 2, gap.end ());
  return gap[gap.size () / 2];
}

} // namespace

int
main (int argc, char **argv)
{
  if (argc < 4)
  {
    std::fprintf (stderr, "usage: %s OUT_DIR FRAME.pcd FRAME.pcd [FRAME.pcd...]\n", argv[0]);
    return 2;
  }
  const std::filesystem::path out_dir = argv[1];
  if (!std::filesystem::is_directory (out_dir))
  {
    std::fprintf (stderr, "error: %s is not a folder\n", argv[1]);
    return 2;
  }
  std::vector<Cloud::Ptr> frames;
  std::vector<std::string> names;
  for (int a = 2; a < argc; ++a)
  {
    frames.emplace_back (new Cloud);
    if (pcl::io::loadPCDFile (argv[a], *frames.back ()) < 0 || frames.back ()->empty ())
    {
      std::fprintf (stderr, "error: cannot read %s\n", argv[a]);
      return 2;
    }
    names.push_back (std::filesystem::path (argv[a]).filename ().string ());
  }

  // 1. Registration, on copies downsampled to 1/200 and 1/800 of the first frame's extent.
  pcl::StopWatch watch;
  Eigen::Vector4f lo, hi;
  {
    Cloud finite;
    pcl::Indices kept;
    pcl::removeNaNFromPointCloud (*frames[0], finite, kept);
    pcl::getMinMax3D (finite, lo, hi);
  }
  const float leaf = (hi - lo).head<3> ().norm () / 200.0f;
  std::vector<Cloud::Ptr> coarse, fine;
  for (const auto &frame : frames)
  {
    coarse.push_back (downsample (*frame, leaf));
    fine.push_back (downsample (*frame, leaf / 4.0f));
  }
  std::vector<Eigen::Matrix4f> to_first (frames.size (), Eigen::Matrix4f::Identity ());
  Eigen::Matrix4f motion = Eigen::Matrix4f::Identity ();  // the previous pair's, as the guess
  bool ok = true;
  for (std::size_t t = 1; t < frames.size (); ++t)
  {
    // Coarse to fine: the leaf-sized grid with a wide search, then a 4x finer grid.
    bool converged = true;
    double fitness = 0.0;
    for (const auto *level : {&coarse, &fine})
    {
      const float size = level == &coarse ? leaf : leaf / 4.0f;
      pcl::IterativeClosestPoint<PointT, PointT> icp;
      icp.setInputSource ((*level)[t]);
      icp.setInputTarget ((*level)[t - 1]);
      icp.setMaxCorrespondenceDistance (level == &coarse ? 10.0 * size : 3.0 * size);
      icp.setMaximumIterations (100);
      icp.setTransformationEpsilon (1e-8);
      Cloud aligned;
      icp.align (aligned, motion);
      converged = converged && icp.hasConverged ();
      if (icp.hasConverged ())
        motion = icp.getFinalTransformation ();
      fitness = icp.getFitnessScore ();
    }
    to_first[t] = to_first[t - 1] * motion;
    Cloud::Ptr moved (new Cloud);
    pcl::transformPointCloud (*fine[t], *moved, motion);
    const double before = medianGap (fine[t], fine[t - 1]);
    const double after = medianGap (moved, fine[t - 1]);
    std::printf ("ICP %s -> %s: %s, fitness %.4g; median gap to the previous frame %.4g -> %.4g\n",
                 names[t].c_str (), names[t - 1].c_str (), converged ? "converged" : "NOT converged",
                 fitness, before, after);
    ok = ok && converged && after < before;
  }
  std::printf ("registration: %.2f s (voxel leaf %.3g)\n", watch.getTimeSeconds (), leaf);

  // 2. Denoising in frame 0's coordinates, frames streamed through the sequence filter.
  watch.reset ();
  pcl_graph_denoise::GraphSequenceSmoothing<PointT> sequence;
  std::vector<Cloud::Ptr> denoised;
  for (std::size_t t = 0; t < frames.size (); ++t)
  {
    Cloud::Ptr registered (new Cloud);
    pcl::transformPointCloud (*frames[t], *registered, to_first[t]);
    Cloud::Ptr ready;
    if (!sequence.push (registered, ready))
      return 1;
    if (ready)
      denoised.push_back (ready);
  }
  std::vector<Cloud::Ptr> rest;
  if (!sequence.flush (rest))
    return 1;
  denoised.insert (denoised.end (), rest.begin (), rest.end ());
  std::printf ("denoising: %.2f s for %zu frames (GraphSequenceSmoothing, Tikhonov, k2 = %d, window %d)\n",
               watch.getTimeSeconds (), frames.size (), sequence.getKTemporal (), sequence.getTemporalWindow ());

  // 3. Back into each frame's own coordinates.
  for (std::size_t t = 0; t < frames.size (); ++t)
  {
    Cloud back;
    pcl::transformPointCloud (*denoised[t], back, Eigen::Matrix4f (to_first[t].inverse ()));
    const std::string path = (out_dir / names[t]).string ();
    if (pcl::io::savePCDFileBinary (path, back) != 0)
      return 1;
    std::printf ("wrote %s (%zu points)\n", path.c_str (), back.size ());
  }
  if (!ok)
    std::fprintf (stderr, "error: a registration did not converge or did not bring the frames closer\n");
  return ok ? 0 : 1;
}

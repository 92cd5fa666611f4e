/*
 * pcl_graph_denoise: graph-signal-processing point cloud denoising for PCL.
 * SPDX-License-Identifier: BSD-3-Clause
 *
 * The main job on the built-in default input: generates a noisy scan of a table
 * scene with outliers, removes the outliers and smooths the rest with the library's
 * filters at their data-derived defaults (GraphDegreeOutlierRemoval, then
 * GraphTVSmoothing), writes both clouds as PCD files and reports what it did.
 *
 *   pcl_graph_denoise_demo [output_directory]     (default: the current directory;
 *                                                   created when missing)
 */
#include <pcl_graph_denoise/graph_degree_outlier_removal.h>
#include <pcl_graph_denoise/graph_tv_smoothing.h>

#include "synthetic.h"

#include <pcl/io/pcd_io.h>

#include <chrono>
#include <cstdio>
#include <exception>
#include <filesystem>
#include <system_error>
#include <string>

namespace {

double
secondsSince (std::chrono::steady_clock::time_point start)
{
  return std::chrono::duration<double> (std::chrono::steady_clock::now () - start).count ();
}

} // namespace

int
main (int argc, char **argv)
{
  if (argc > 2 || (argc == 2 && (std::string (argv[1]) == "-h" || std::string (argv[1]) == "--help")))
  {
    std::printf ("usage: %s [output_directory]\n", argv[0]);
    return argc > 2 ? 1 : 0;
  }
  const std::string dir = argc == 2 ? std::string (argv[1]) + "/" : std::string ();
  using Cloud = pcl::PointCloud<pcl::PointXYZ>;

  auto start = std::chrono::steady_clock::now ();
  std::vector<bool> truth;
  Cloud::Ptr input (new Cloud (pcl_graph_denoise::synthetic::demoScene (42, &truth)));
  std::size_t true_outliers = 0;
  for (bool t : truth)
    true_outliers += t;
  std::printf ("input: generated table scene, %zu points (%zu injected outliers, 3 mm noise) "
               "in %.3f s\n",
               input->size (), true_outliers, secondsSince (start));

  // Outlier removal with every parameter derived from the data.
  start = std::chrono::steady_clock::now ();
  pcl_graph_denoise::GraphDegreeOutlierRemoval<pcl::PointXYZ> outliers (true);
  outliers.setInputCloud (input);
  Cloud::Ptr cleaned (new Cloud);
  outliers.filter (*cleaned);
  const double t_outliers = secondsSince (start);
  std::size_t hits = 0;
  for (const auto index : *outliers.getRemovedIndices ())
    hits += truth[index];
  const auto removed = outliers.getRemovedIndices ()->size ();
  std::printf ("GraphDegreeOutlierRemoval: epsilon %.4f m, theta %.4f m, tau %.3f -> removed "
               "%zu points (%zu of the %zu injected outliers, %zu surface points) in %.3f s\n",
               outliers.getUsedRadius (), outliers.getUsedSigma (),
               outliers.getUsedDegreeThreshold (), removed, hits, true_outliers, removed - hits,
               t_outliers);

  // Total-variation smoothing of the remaining points, every parameter derived too.
  start = std::chrono::steady_clock::now ();
  pcl_graph_denoise::GraphTVSmoothing<pcl::PointXYZ> smoother;
  smoother.setInputCloud (cleaned);
  Cloud::Ptr smoothed (new Cloud);
  smoother.filter (*smoothed);
  const double t_smooth = secondsSince (start);
  const auto &report = smoother.getSolverReport ();
  std::printf ("GraphTVSmoothing: estimated noise %.4f m, theta %.4f m, gamma %.5f m, %d "
               "primal-dual iterations (relative gap %.1e) in %.3f s\n",
               smoother.getEstimatedNoise (), smoother.getUsedSigma (), smoother.getUsedGamma (),
               report.iterations, report.residual, t_smooth);
  const double before = pcl_graph_denoise::synthetic::demoSceneError (*cleaned);
  const double after = pcl_graph_denoise::synthetic::demoSceneError (*smoothed);
  std::printf ("mean distance of the kept surface points to the true scene: %.2f mm -> %.2f mm\n",
               1000.0 * before, 1000.0 * after);

  start = std::chrono::steady_clock::now ();
  const std::string in_path = dir + "demo_input.pcd", out_path = dir + "demo_output.pcd";
  bool written = false;
  try
  {
    std::error_code ignored;  // an existing folder is fine; failures show when writing
    if (!dir.empty ())
      std::filesystem::create_directories (dir, ignored);
    written = pcl::io::savePCDFileBinary (in_path, *input) == 0 &&
              pcl::io::savePCDFileBinary (out_path, *smoothed) == 0;
  }
  catch (const std::exception &)  // PCL's writer throws pcl::IOException
  {
    written = false;
  }
  if (!written)
  {
    std::fprintf (stderr, "error: cannot write %s and %s\n", in_path.c_str (), out_path.c_str ());
    return 1;
  }
  std::printf ("wrote %s (%zu points) and %s (%zu points) in %.3f s\n", in_path.c_str (),
               input->size (), out_path.c_str (), smoothed->size (), secondsSince (start));
  std::printf ("compare them with: pcl_viewer -multiview 1 %s %s\n", in_path.c_str (),
               out_path.c_str ());
  return 0;
}

/*
 * pcl_graph_denoise: graph-signal-processing point cloud denoising for PCL.
 * SPDX-License-Identifier: BSD-3-Clause
 *
 * libFuzzer target: arbitrary bytes as a .pcd file and as a .ply file, through the
 * command-line tool's load-and-filter path (tools/cloud_io.*, tools/cloud_fields.*, then
 * GraphDegreeOutlierRemoval and both smoothers with small iteration caps, as the tool
 * runs them). Aborts when loadCloud throws anything but tools::Error, when a filter
 * throws, or when a result breaks the tool's invariants (sizes, fields, finite output).
 */
#include "cloud_fields.h"
#include "cloud_io.h"

#include "fuzz_check.h"

#include <pcl_graph_denoise/graph_degree_outlier_removal.h>
#include <pcl_graph_denoise/graph_tikhonov_smoothing.h>
#include <pcl_graph_denoise/graph_tv_smoothing.h>

#include <pcl/common/point_tests.h>
#include <pcl/console/print.h>

#include <unistd.h>

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <exception>
#include <string>

namespace {

using namespace pcl_graph_denoise;
using Cloud = pcl::PointCloud<pcl::PointXYZ>;

std::string base_path;

void
removeFiles ()
{
  std::remove ((base_path + ".pcd").c_str ());
  std::remove ((base_path + ".ply").c_str ());
}

/** Outliers, then a smoothing step, as the tool runs them, with the tool's checks. */
void
filterCloud (tools::CloudFile &file, const std::string &path, bool tv)
{
  const std::size_t size = std::size_t (file.cloud.width) * file.cloud.height;
  FUZZ_CHECK (size > 0);
  tools::XyzFields xyz (file.cloud, path);  // throws tools::Error without x, y, z
  xyz.centreOn (file.cloud);
  Cloud::Ptr input = xyz.extract (file.cloud);
  FUZZ_CHECK (input->size () == size);
  std::size_t finite_points = 0;
  for (const auto &p : *input)
    finite_points += pcl::isXYZFinite (p);
  if (finite_points == 0)
    return;  // the tool stops here with an error

  // -outliers: every point is kept or removed, never both.
  GraphDegreeOutlierRemoval<pcl::PointXYZ> outliers (true);
  outliers.setNumberOfThreads (1);
  outliers.setInputCloud (input);
  pcl::Indices kept;
  outliers.filter (kept);
  const pcl::Indices &gone = *outliers.getRemovedIndices ();
  if (kept.size () + gone.size () != size)
  {
    // Only an error may leave the split incomplete, and then both are empty.
    FUZZ_CHECK (kept.empty () && gone.empty ());
    return;
  }
  for (const auto i : kept)
    FUZZ_CHECK (i >= 0 && std::size_t (i) < size && pcl::isXYZFinite ((*input)[i]));
  pcl::PCLPointCloud2 removed;
  tools::appendPoints (removed, tools::selectPoints (file.cloud, gone));
  FUZZ_CHECK (std::size_t (removed.width) * removed.height == gone.size ());
  file.cloud = tools::selectPoints (file.cloud, kept);
  if (kept.empty ())
    return;

  // -tikhonov or -tv: size and order kept, only finite points move, to finite places.
  input = xyz.extract (file.cloud);
  GraphTikhonovSmoothing<pcl::PointXYZ> tikhonov;
  GraphTVSmoothing<pcl::PointXYZ> total_variation;
  GraphSmoothing<pcl::PointXYZ> &smoother =
      tv ? static_cast<GraphSmoothing<pcl::PointXYZ> &> (total_variation) : tikhonov;
  smoother.setMaximumIterations (30);
  smoother.setNumberOfThreads (1);
  smoother.setInputCloud (input);
  Cloud output;
  smoother.filter (output);
  if (output.empty ())
    return;  // an error, reported by the filter
  FUZZ_CHECK (output.size () == input->size ());
  for (std::size_t i = 0; i < output.size (); ++i)
    FUZZ_CHECK (pcl::isXYZFinite (output[i]));
  xyz.writeBack (file.cloud, *input, output);
  const Cloud::Ptr after = xyz.extract (file.cloud);
  FUZZ_CHECK (after->size () == output.size ());
}

void
loadAndFilter (const std::uint8_t *data, std::size_t size, const char *extension, bool tv)
{
  const std::string path = base_path + extension;
  std::FILE *f = std::fopen (path.c_str (), "wb");
  FUZZ_CHECK (f != nullptr);
  FUZZ_CHECK (size == 0 || std::fwrite (data, 1, size, f) == size);
  std::fclose (f);
  try
  {
    tools::CloudFile file = tools::loadCloud (path);
    filterCloud (file, path, tv);
  }
  catch (const tools::Error &)
  {
    // A one-line error of the tool: the expected outcome of bad bytes.
  }
  catch (const std::exception &e)
  {
    std::fprintf (stderr, "fuzz_cloud_file: unexpected exception: %s\n", e.what ());
    std::abort ();
  }
}

} // namespace

extern "C" int
LLVMFuzzerInitialize (int *, char ***)
{
  pcl::console::setVerbosityLevel (pcl::console::L_ALWAYS);
  const char *dir = std::getenv ("TMPDIR");
  base_path = std::string (access ("/dev/shm", W_OK) == 0 ? "/dev/shm" : dir ? dir : "/tmp") +
              "/pgd_fuzz_cloud_file-" + std::to_string (::getpid ());
  std::atexit (removeFiles);
  return 0;
}

extern "C" int
LLVMFuzzerTestOneInput (const std::uint8_t *data, std::size_t size)
{
  // The last byte picks the smoother, so that both see every file.
  const bool tv = size > 0 && (data[size - 1] & 1);
  loadAndFilter (data, size, ".pcd", tv);
  loadAndFilter (data, size, ".ply", tv);
  return 0;
}

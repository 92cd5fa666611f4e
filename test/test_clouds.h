/*
 * pcl_graph_denoise: graph-signal-processing point cloud denoising for PCL.
 * SPDX-License-Identifier: BSD-3-Clause
 */
#pragma once

/* Test helpers: clouds of any point type with every field set, and exact
 * comparisons of clouds and points (all bytes of every field). */

#include <pcl/common/io.h>
#include <pcl/point_cloud.h>
#include <pcl/point_types.h>

#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <random>
#include <string>
#include <vector>

namespace pcl_graph_denoise {
namespace testing {

/** The positions of `xyz` in a cloud of PointT whose other fields (colour, normal,
 *  intensity, curvature...) hold distinct values derived from the index. */
template <typename PointT>
typename pcl::PointCloud<PointT>::Ptr
withFields (const pcl::PointCloud<pcl::PointXYZ> &xyz)
{
  auto cloud = std::make_shared<pcl::PointCloud<PointT>> ();
  cloud->resize (xyz.size ());
  for (std::size_t i = 0; i < xyz.size (); ++i)
  {
    PointT &p = (*cloud)[i];
    // Fill every byte first so that fields we do not name are set too.
    auto *bytes = reinterpret_cast<unsigned char *> (&p);
    for (std::size_t b = 0; b < sizeof (PointT); ++b)
      bytes[b] = static_cast<unsigned char> ((i * 31 + b * 7) % 251);
    p.x = xyz[i].x;
    p.y = xyz[i].y;
    p.z = xyz[i].z;
  }
  cloud->header.frame_id = "test_frame";
  cloud->header.stamp = 123456;
  return cloud;
}

template <typename PointT>
pcl::PointCloud<PointT>
deepCopy (const pcl::PointCloud<PointT> &cloud)
{
  return cloud;
}

template <typename PointT>
bool
samePoint (const PointT &a, const PointT &b)
{
  return std::memcmp (&a, &b, sizeof (PointT)) == 0;
}

template <typename PointT>
bool
sameCloud (const pcl::PointCloud<PointT> &a, const pcl::PointCloud<PointT> &b)
{
  if (a.size () != b.size () || a.width != b.width || a.height != b.height ||
      a.is_dense != b.is_dense || a.header.frame_id != b.header.frame_id ||
      a.header.stamp != b.header.stamp)
    return false;
  for (std::size_t i = 0; i < a.size (); ++i)
    if (!samePoint (a[i], b[i]))
      return false;
  return true;
}

/** Path of a file under ../shared/data (the environment variable
 *  PCL_GRAPH_DENOISE_SHARED_DATA overrides the folder). */
inline std::string
sharedDataPath (const std::string &relative)
{
  const char *env = std::getenv ("PCL_GRAPH_DENOISE_SHARED_DATA");
  return std::string (env ? env : PCL_GRAPH_DENOISE_SHARED_DATA) + "/" + relative;
}

/** True when running under CI (CI=true), where shared data must be present. */
inline bool
underCI ()
{
  const char *ci = std::getenv ("CI");
  return ci && std::string (ci) == "true";
}

/** What recedingFloor's points are. */
enum class FloorPart : unsigned char
{
  NEAR,     ///< the floor within 5 units of the scanner
  FAR,      ///< the floor beyond 5 units, up to 11 times as sparse as the nearest
  OUTLIER,  ///< uniform in the box above it
};

/** A floor as a scanner sees it: the plane z = 0 over x in [0, 10], y in [0, 1], whose
 *  spacing grows with x from 0.01 to 0.11 (a scanner's grows with the range), points
 *  jittered by a quarter of it and with a normal noise of 2% of it; then `outliers`
 *  points uniform in [0, 10] x [0, 1] x [0.5, 3]. `parts` receives what each point is. */
inline pcl::PointCloud<pcl::PointXYZ>
recedingFloor (std::size_t outliers, unsigned seed, std::vector<FloorPart> &parts)
{
  std::mt19937 rng (seed);
  std::uniform_real_distribution<float> jitter (-0.25f, 0.25f);
  std::normal_distribution<float> noise (0.0f, 0.02f);
  pcl::PointCloud<pcl::PointXYZ> cloud;
  parts.clear ();
  for (float x = 0.0f; x <= 10.0f; x += 0.01f * (1.0f + x))
  {
    const float h = 0.01f * (1.0f + x);
    for (float y = 0.0f; y < 1.0f; y += h)
    {
      cloud.push_back (pcl::PointXYZ (x + h * jitter (rng), y + h * jitter (rng), h * noise (rng)));
      parts.push_back (x > 5.0f ? FloorPart::FAR : FloorPart::NEAR);
    }
  }
  std::uniform_real_distribution<float> u (0.0f, 1.0f);
  for (std::size_t i = 0; i < outliers; ++i)
  {
    cloud.push_back (pcl::PointXYZ (10.0f * u (rng), u (rng), 0.5f + 2.5f * u (rng)));
    parts.push_back (FloorPart::OUTLIER);
  }
  return cloud;
}

} // namespace testing
} // namespace pcl_graph_denoise

/** Skips the test, visibly, when a shared data file is absent (a user's clone);
 *  fails it under CI, so CI never passes by skipping. */
#define PGD_REQUIRE_SHARED_FILE(path)                                                       \
  do                                                                                         \
  {                                                                                          \
    if (!std::filesystem::exists (path))                                                     \
    {                                                                                        \
      if (::pcl_graph_denoise::testing::underCI ())                                          \
        FAIL () << "shared data missing under CI: " << (path);                               \
      GTEST_SKIP () << "shared data absent, test skipped: " << (path);                       \
    }                                                                                        \
  } while (0)

/*
 * pcl_graph_denoise: graph-signal-processing point cloud denoising for PCL.
 * SPDX-License-Identifier: BSD-3-Clause
 *
 * Real data from ../shared/data (skipped visibly where absent, failed under CI).
 */
#include <pcl_graph_denoise/graph_degree_outlier_removal.h>

#include "test_clouds.h"

#include <gtest/gtest.h>

#include <pcl/io/ply_io.h>

#include <algorithm>

using namespace pcl_graph_denoise::testing;

namespace {

/** Median of each coordinate: a centre that gross outliers do not move. */
Eigen::Vector3f
medianCentre (const pcl::PointCloud<pcl::PointXYZRGB> &cloud)
{
  Eigen::Vector3f centre;
  for (int d = 0; d < 3; ++d)
  {
    std::vector<float> v;
    for (const auto &p : cloud)
      v.push_back (p.getVector3fMap () (d));
    std::nth_element (v.begin (), v.begin () + v.size () / 2, v.end ());
    centre (d) = v[v.size () / 2];
  }
  return centre;
}

} // namespace

TEST (SharedData, FountainGrossOutliersAreRemovedWithDefaults)
{
  const std::string path = sharedDataPath ("real/fountain_sfm/fountain_sfm_11view.ply");
  PGD_REQUIRE_SHARED_FILE (path);
  auto cloud = std::make_shared<pcl::PointCloud<pcl::PointXYZRGB>> ();
  ASSERT_EQ (pcl::io::loadPLYFile (path, *cloud), 0);
  ASSERT_EQ (cloud->size (), 13140u);
  const auto before = deepCopy (*cloud);

  pcl_graph_denoise::GraphDegreeOutlierRemoval<pcl::PointXYZRGB> filter (true);
  filter.setInputCloud (cloud);
  pcl::Indices kept;
  filter.filter (kept);
  EXPECT_TRUE (sameCloud (*cloud, before));

  // The fountain is a few units across; SfM's gross outliers lie tens to hundreds of
  // units away. Every point farther than 30 units from the median must go, and nine in
  // ten points within 5 units (the fountain and the wall behind it) must stay: SfM also
  // leaves isolated points in front of the fountain, which may go.
  const Eigen::Vector3f centre = medianCentre (*cloud);
  std::size_t far = 0, far_kept = 0, near = 0, near_kept = 0;
  std::vector<std::uint8_t> is_kept (cloud->size (), 0);
  for (auto i : kept)
    is_kept[i] = 1;
  for (std::size_t i = 0; i < cloud->size (); ++i)
  {
    const float r = ((*cloud)[i].getVector3fMap () - centre).norm ();
    if (r > 30.0f)
      ++far, far_kept += is_kept[i];
    if (r < 5.0f)
      ++near, near_kept += is_kept[i];
  }
  EXPECT_GE (far, 5u);
  EXPECT_EQ (far_kept, 0u);
  EXPECT_GE (double (near_kept), 0.9 * double (near)) << near_kept << " of " << near;
  std::printf ("fountain: %zu points, kept %zu; far (>30) %zu all removed; near (<5) kept %zu "
               "of %zu\n",
               cloud->size (), kept.size (), far, near_kept, near);
}

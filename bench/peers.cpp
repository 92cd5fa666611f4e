/*
 * pcl_graph_denoise: graph-signal-processing point cloud denoising for PCL.
 * SPDX-License-Identifier: BSD-3-Clause
 */
#include "peers.h"

#include <pcl/kdtree/kdtree_flann.h>
#include <pcl/surface/mls.h>

#include <CGAL/Simple_cartesian.h>
#include <CGAL/bilateral_smooth_point_set.h>
#include <CGAL/jet_estimate_normals.h>
#include <CGAL/jet_smooth_point_set.h>
#include <CGAL/mst_orient_normals.h>
#include <CGAL/property_map.h>
#include <CGAL/remove_outliers.h>
#include <CGAL/wlop_simplify_and_regularize_point_set.h>

#include <algorithm>
#include <iterator>
#include <thread>
#include <utility>

namespace pcl_graph_denoise {
namespace peers {

namespace {

#ifdef CGAL_LINKED_WITH_TBB
using Concurrency = CGAL::Parallel_tag;
#else
using Concurrency = CGAL::Sequential_tag;
#endif

using Kernel = CGAL::Simple_cartesian<double>;
using Point3 = Kernel::Point_3;
using Vector3 = Kernel::Vector_3;

std::vector<Point3>
toCgal (const Cloud &cloud)
{
  std::vector<Point3> points;
  points.reserve (cloud.size ());
  for (const auto &p : cloud)
    points.emplace_back (p.x, p.y, p.z);
  return points;
}

pcl::PointXYZ
toPcl (const Point3 &p)
{
  return {float (p.x ()), float (p.y ()), float (p.z ())};
}

} // namespace

double
meanKthNeighbourDistance (const Cloud &cloud, int k)
{
  pcl::KdTreeFLANN<pcl::PointXYZ> tree;
  tree.setInputCloud (cloud.makeShared ());
  pcl::Indices index;
  std::vector<float> d2;
  double sum = 0.0;
  std::size_t count = 0;
  const std::size_t step = std::max<std::size_t> (1, cloud.size () / 2000);
  for (std::size_t i = 0; i < cloud.size (); i += step, ++count)
  {
    tree.nearestKSearch (cloud[i], k + 1, index, d2);
    sum += std::sqrt (d2.back ());
  }
  return sum / double (std::max<std::size_t> (count, 1));
}

Cloud
movingLeastSquares (const Cloud &cloud, double radius)
{
  pcl::MovingLeastSquares<pcl::PointXYZ, pcl::PointXYZ> mls;
  mls.setInputCloud (cloud.makeShared ());
  mls.setPolynomialOrder (2);
  mls.setSearchRadius (radius);
  mls.setNumberOfThreads (std::max (1u, std::thread::hardware_concurrency ()));
  mls.setComputeNormals (false);
  Cloud out;
  mls.process (out);
  return out;
}

Cloud
jetSmooth (const Cloud &cloud, unsigned k)
{
  std::vector<Point3> points = toCgal (cloud);
  CGAL::jet_smooth_point_set<Concurrency> (points, k);
  Cloud out;
  for (const auto &p : points)
    out.push_back (toPcl (p));
  return out;
}

Cloud
bilateralSmooth (const Cloud &cloud, unsigned k, double sharpness_angle, int iterations)
{
  using PointNormal = std::pair<Point3, Vector3>;
  std::vector<PointNormal> points;
  for (const auto &p : toCgal (cloud))
    points.emplace_back (p, Vector3 (0, 0, 0));
  const auto parameters = CGAL::parameters::point_map (CGAL::First_of_pair_property_map<PointNormal> ())
                              .normal_map (CGAL::Second_of_pair_property_map<PointNormal> ());
  CGAL::jet_estimate_normals<Concurrency> (points, 18, parameters);
  CGAL::mst_orient_normals (points, 18, parameters);
  for (int i = 0; i < iterations; ++i)
    CGAL::bilateral_smooth_point_set<Concurrency> (points, k,
                                                   parameters.sharpness_angle (sharpness_angle));
  Cloud out;
  for (const auto &p : points)
    out.push_back (toPcl (p.first));
  return out;
}

Cloud
wlop (const Cloud &cloud, double neighbour_radius)
{
  std::vector<Point3> points = toCgal (cloud);  // WLOP reorders its input
  std::vector<Point3> output;
  CGAL::wlop_simplify_and_regularize_point_set<Concurrency> (
      points, std::back_inserter (output),
      CGAL::parameters::select_percentage (100.0).neighbor_radius (neighbour_radius > 0.0 ? neighbour_radius
                                                                                          : -1.0));
  Cloud out;
  for (const auto &p : output)
    out.push_back (toPcl (p));
  return out;
}

std::vector<bool>
cgalRemoveOutliers (const Cloud &cloud, unsigned k, double threshold_percent,
                    double threshold_distance)
{
  using Indexed = std::pair<Point3, std::size_t>;
  std::vector<Indexed> points;
  const std::vector<Point3> cgal = toCgal (cloud);
  for (std::size_t i = 0; i < cgal.size (); ++i)
    points.emplace_back (cgal[i], i);
  const auto first_removed = CGAL::remove_outliers<Concurrency> (
      points, k,
      CGAL::parameters::point_map (CGAL::First_of_pair_property_map<Indexed> ())
          .threshold_percent (threshold_percent)
          .threshold_distance (threshold_distance));
  std::vector<bool> removed (cloud.size (), false);
  for (auto it = first_removed; it != points.end (); ++it)
    removed[it->second] = true;
  return removed;
}

} // namespace peers
} // namespace pcl_graph_denoise

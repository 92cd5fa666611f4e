/*
 * pcl_graph_denoise: graph-signal-processing point cloud denoising for PCL.
 * SPDX-License-Identifier: BSD-3-Clause
 */
#include "synthetic.h"

#include <pcl/common/common.h>

#include <algorithm>
#include <cmath>
#include <random>

namespace pcl_graph_denoise {
namespace synthetic {

core::PointMatrix
toMatrix (const Cloud &cloud)
{
  core::PointMatrix m (static_cast<Eigen::Index> (cloud.size ()), 3);
  for (std::size_t i = 0; i < cloud.size (); ++i)
    m.row (static_cast<Eigen::Index> (i)) = cloud[i].getVector3fMap ().transpose ();
  return m;
}

namespace {

constexpr double kPi = 3.14159265358979323846;

void
addNoise (Cloud &cloud, double noise, std::mt19937_64 &rng)
{
  std::normal_distribution<double> gauss (0.0, 1.0);
  for (auto &p : cloud)
  {
    p.x = static_cast<float> (p.x + noise * gauss (rng));
    p.y = static_cast<float> (p.y + noise * gauss (rng));
    p.z = static_cast<float> (p.z + noise * gauss (rng));
  }
}

pcl::PointXYZ
onSphere (std::mt19937_64 &rng, double radius)
{
  std::uniform_real_distribution<double> u (-1.0, 1.0), phi (0.0, 2.0 * kPi);
  const double z = u (rng), a = phi (rng), r = std::sqrt (std::max (0.0, 1.0 - z * z));
  return {float (radius * r * std::cos (a)), float (radius * r * std::sin (a)), float (radius * z)};
}

/** A point uniform on the surface of the axis-aligned box [lo, hi]. */
pcl::PointXYZ
onBox (std::mt19937_64 &rng, const Eigen::Vector3d &lo, const Eigen::Vector3d &hi)
{
  const Eigen::Vector3d e = hi - lo;
  const double areas[3] = {e.y () * e.z (), e.x () * e.z (), e.x () * e.y ()};
  std::uniform_real_distribution<double> u (0.0, 1.0);
  double pick = u (rng) * 2.0 * (areas[0] + areas[1] + areas[2]);
  int axis = 0;
  while (axis < 2 && pick >= 2.0 * areas[axis])
    pick -= 2.0 * areas[axis++];
  Eigen::Vector3d p (lo.x () + u (rng) * e.x (), lo.y () + u (rng) * e.y (),
                     lo.z () + u (rng) * e.z ());
  p (axis) = pick < areas[axis] ? lo (axis) : hi (axis);
  return {float (p.x ()), float (p.y ()), float (p.z ())};
}

} // namespace

Cloud
noisySphere (std::size_t n, double radius, double noise, std::uint64_t seed)
{
  std::mt19937_64 rng (seed);
  Cloud cloud;
  cloud.reserve (n);
  for (std::size_t i = 0; i < n; ++i)
    cloud.push_back (onSphere (rng, radius));
  addNoise (cloud, noise, rng);
  return cloud;
}

Cloud
noisyPlane (std::size_t n, double noise, std::uint64_t seed)
{
  std::mt19937_64 rng (seed);
  std::uniform_real_distribution<double> u (-1.0, 1.0);
  Cloud cloud;
  cloud.reserve (n);
  for (std::size_t i = 0; i < n; ++i)
    cloud.push_back (pcl::PointXYZ (float (u (rng)), float (u (rng)), 0.0f));
  addNoise (cloud, noise, rng);
  return cloud;
}

Cloud
noisyCube (std::size_t n, double noise, std::uint64_t seed)
{
  std::mt19937_64 rng (seed);
  Cloud cloud;
  cloud.reserve (n);
  for (std::size_t i = 0; i < n; ++i)
    cloud.push_back (onBox (rng, Eigen::Vector3d::Constant (-1.0), Eigen::Vector3d::Constant (1.0)));
  addNoise (cloud, noise, rng);
  return cloud;
}

std::vector<bool>
addUniformOutliers (Cloud &cloud, double fraction, double margin, std::uint64_t seed, bool cubic)
{
  std::vector<bool> is_outlier (cloud.size (), false);
  if (cloud.empty ())
    return is_outlier;
  pcl::PointXYZ lo, hi;
  pcl::getMinMax3D (cloud, lo, hi);
  const Eigen::Vector3d centre = 0.5 * (lo.getVector3fMap () + hi.getVector3fMap ()).cast<double> ();
  Eigen::Vector3d extent = (hi.getVector3fMap () - lo.getVector3fMap ()).cast<double> ();
  if (cubic)
    extent.setConstant (extent.maxCoeff ());
  const Eigen::Vector3d a = centre - (0.5 + margin) * extent;
  const Eigen::Vector3d b = centre + (0.5 + margin) * extent;
  std::mt19937_64 rng (seed);
  std::uniform_real_distribution<double> u (0.0, 1.0);
  const auto count = static_cast<std::size_t> (std::llround (fraction * double (cloud.size ())));
  for (std::size_t i = 0; i < count; ++i)
  {
    cloud.push_back (pcl::PointXYZ (float (a.x () + u (rng) * (b.x () - a.x ())),
                                    float (a.y () + u (rng) * (b.y () - a.y ())),
                                    float (a.z () + u (rng) * (b.z () - a.z ()))));
    is_outlier.push_back (true);
  }
  return is_outlier;
}

namespace {

// The demo scene's geometry, shared by demoScene and demoSceneError.
const Eigen::Vector3d kBoxLo (-0.45, -0.2, 0.0), kBoxHi (-0.15, 0.1, 0.3);
const Eigen::Vector3d kBallCentre (0.25, 0.0, 0.12);
constexpr double kBallRadius = 0.12;

double
distanceToBox (const Eigen::Vector3d &p, const Eigen::Vector3d &lo, const Eigen::Vector3d &hi)
{
  const Eigen::Vector3d centre = 0.5 * (lo + hi), half = 0.5 * (hi - lo);
  const Eigen::Vector3d d = (p - centre).cwiseAbs () - half;
  const double outside = d.cwiseMax (0.0).norm ();
  return outside > 0.0 ? outside : -d.maxCoeff ();
}

} // namespace

double
distanceToPlane (const Eigen::Vector3d &p)
{
  return std::abs (p.z ());
}

double
distanceToUnitSphere (const Eigen::Vector3d &p)
{
  return std::abs (p.norm () - 1.0);
}

double
distanceToCube (const Eigen::Vector3d &p)
{
  return distanceToBox (p, Eigen::Vector3d::Constant (-1.0), Eigen::Vector3d::Constant (1.0));
}

double
meanDistance (const Cloud &cloud, const SurfaceDistance &distance)
{
  double sum = 0.0;
  for (const auto &p : cloud)
    sum += distance (Eigen::Vector3d (p.x, p.y, p.z));
  return cloud.empty () ? 0.0 : sum / double (cloud.size ());
}

double
demoSceneError (const Cloud &cloud)
{
  double sum = 0.0;
  std::size_t count = 0;
  for (const auto &q : cloud)
  {
    const Eigen::Vector3d p (q.x, q.y, q.z);
    // The table top is the rectangle z = 0; the box's bottom face lies on it.
    const Eigen::Vector3d on_table (std::clamp (p.x (), -0.6, 0.6), std::clamp (p.y (), -0.4, 0.4), 0.0);
    const double d = std::min ({(p - on_table).norm (), distanceToBox (p, kBoxLo, kBoxHi),
                                std::abs ((p - kBallCentre).norm () - kBallRadius)});
    if (d < 0.02)
    {
      sum += d;
      ++count;
    }
  }
  return count ? sum / count : 0.0;
}

Cloud
demoScene (std::uint64_t seed, std::vector<bool> *is_outlier)
{
  std::mt19937_64 rng (seed);
  std::uniform_real_distribution<double> u (0.0, 1.0);
  Cloud cloud;
  // Table top 1.2 m x 0.8 m with a 0.3 m box and a ball of radius 0.12 m on it, at
  // a density of about one point per 5 mm x 5 mm.
  const double density = 1.0 / (0.005 * 0.005);
  const auto table = static_cast<std::size_t> (1.2 * 0.8 * density);
  for (std::size_t i = 0; i < table; ++i)
    cloud.push_back (pcl::PointXYZ (float (-0.6 + 1.2 * u (rng)), float (-0.4 + 0.8 * u (rng)), 0.0f));
  const auto box = static_cast<std::size_t> (5.0 * 0.09 * density);
  for (std::size_t i = 0; i < box; ++i)
  {
    pcl::PointXYZ p = onBox (rng, kBoxLo, kBoxHi);
    if (p.z > 0.0f)  // the bottom face lies on the table and is not seen
      cloud.push_back (p);
  }
  const auto ball = static_cast<std::size_t> (4.0 * kPi * kBallRadius * kBallRadius * density);
  for (std::size_t i = 0; i < ball; ++i)
  {
    pcl::PointXYZ p = onSphere (rng, kBallRadius);
    p.getVector3fMap () += kBallCentre.cast<float> ();
    cloud.push_back (p);
  }
  addNoise (cloud, 0.003, rng);
  std::vector<bool> outliers = addUniformOutliers (cloud, 0.04, 0.05, seed + 1);
  if (is_outlier)
    *is_outlier = std::move (outliers);
  return cloud;
}

} // namespace synthetic
} // namespace pcl_graph_denoise

/*
 * pcl_graph_denoise: graph-signal-processing point cloud denoising for PCL.
 * SPDX-License-Identifier: BSD-3-Clause
 */
#pragma once

/* Seeded synthetic clouds with known surfaces, shared by the demo, the benchmarks
 * and the tests (the project ships no third-party data of its own). */

#include <pcl_graph_denoise/core/graph.h>

#include <pcl/point_cloud.h>
#include <pcl/point_types.h>

#include <cstdint>
#include <functional>
#include <vector>

namespace pcl_graph_denoise {
namespace synthetic {

using Cloud = pcl::PointCloud<pcl::PointXYZ>;

/** The cloud's positions as the numerical core takes them, one row per point. */
core::PointMatrix
toMatrix (const Cloud &cloud);

/** n points uniform on a sphere of the given radius at the origin, plus isotropic
 *  Gaussian noise of standard deviation `noise`. */
Cloud
noisySphere (std::size_t n, double radius, double noise, std::uint64_t seed);

/** n points uniform on the unit square [-1,1]^2 x {0}, plus Gaussian noise. */
Cloud
noisyPlane (std::size_t n, double noise, std::uint64_t seed);

/** n points uniform on the surface of the cube [-1,1]^3, plus Gaussian noise. */
Cloud
noisyCube (std::size_t n, double noise, std::uint64_t seed);

/** Appends round(fraction x size) points uniform in the cloud's bounding box enlarged
 *  by `margin` (relative to its extent, on each side) and returns, for every point of
 *  the result, whether it is one of the added outliers. With `cubic`, the box is first
 *  widened to its largest side on every axis, so that a flat cloud gets outliers off
 *  its plane. */
std::vector<bool>
addUniformOutliers (Cloud &cloud, double fraction, double margin, std::uint64_t seed,
                    bool cubic = false);

/** The demo's default input: a table top with a box and a ball on it, seen as a
 *  noisy scan (about 60,000 points, metres, noise 3 mm) with 4% outliers.
 *  `is_outlier` receives the ground truth when not null. */
Cloud
demoScene (std::uint64_t seed, std::vector<bool> *is_outlier = nullptr);

/** Exact distances to the true surfaces of noisyPlane, noisySphere (radius 1) and
 *  noisyCube. */
double
distanceToPlane (const Eigen::Vector3d &p);
double
distanceToUnitSphere (const Eigen::Vector3d &p);
double
distanceToCube (const Eigen::Vector3d &p);

/** A distance to a known surface. */
using SurfaceDistance = std::function<double (const Eigen::Vector3d &)>;

/** Mean distance of the points of a cloud to a known surface. */
double
meanDistance (const Cloud &cloud, const SurfaceDistance &distance);

/** Mean distance of the points of a cloud to the demo scene's true surfaces (table
 *  top, box, ball), over the points within 2 cm of them: outliers left in the cloud
 *  do not count. */
double
demoSceneError (const Cloud &cloud);

} // namespace synthetic
} // namespace pcl_graph_denoise

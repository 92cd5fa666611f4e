/*
 * pcl_graph_denoise: graph-signal-processing point cloud denoising for PCL.
 * SPDX-License-Identifier: BSD-3-Clause
 */
#pragma once

/* The peers we are measured against, each called the way its documentation shows, on
 * all threads: PCL's MovingLeastSquares, CGAL's jet, bilateral and WLOP smoothing and
 * CGAL's outlier removal. One place, so that every benchmark runs them the same way. */

#include <pcl/point_cloud.h>
#include <pcl/point_types.h>

#include <vector>

namespace pcl_graph_denoise {
namespace peers {

using Cloud = pcl::PointCloud<pcl::PointXYZ>;

/** Mean distance to the k-th nearest neighbour over a sample of the points (a scale for
 *  the peers' radii). */
double
meanKthNeighbourDistance (const Cloud &cloud, int k);

/** pcl::MovingLeastSquares, polynomial order 2, projection of every point, no
 *  upsampling; one output point per input point. */
Cloud
movingLeastSquares (const Cloud &cloud, double radius);

/** CGAL::jet_smooth_point_set with k neighbours (degree 2 fit, as CGAL's default). */
Cloud
jetSmooth (const Cloud &cloud, unsigned k);

/** CGAL::bilateral_smooth_point_set, `iterations` passes with k neighbours and the given
 *  sharpness angle (degrees), on normals estimated by CGAL::jet_estimate_normals (k = 18)
 *  and oriented by CGAL::mst_orient_normals, as CGAL's example does. */
Cloud
bilateralSmooth (const Cloud &cloud, unsigned k, double sharpness_angle, int iterations);

/** CGAL::wlop_simplify_and_regularize_point_set keeping every point (select percentage
 *  100), with the given neighbour radius (<= 0: CGAL's default, 8 times the average
 *  spacing) and CGAL's default 35 iterations. */
Cloud
wlop (const Cloud &cloud, double neighbour_radius);

/** CGAL::remove_outliers: a point is removed when its score (the square root of the
 *  mean squared distance to its k nearest neighbours) is above `threshold_distance`
 *  and among the top `threshold_percent` percent of scores. Returns, for every point,
 *  whether it was removed. */
std::vector<bool>
cgalRemoveOutliers (const Cloud &cloud, unsigned k, double threshold_percent,
                    double threshold_distance);

} // namespace peers
} // namespace pcl_graph_denoise

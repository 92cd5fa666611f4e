/*
 * pcl_graph_denoise: graph-signal-processing point cloud denoising for PCL.
 * SPDX-License-Identifier: BSD-3-Clause
 */
#pragma once

/** \file noise_level.h
 *  \brief How noisy a point cloud is and how densely its surface is sampled: the basis of
 *  the data-derived smoothing strength. */

#include <pcl_graph_denoise/core/graph.h>

namespace pcl_graph_denoise {
namespace core {

/** \brief What estimateNoise measures. Lengths in the points' units. */
struct NoiseEstimate
{
  /** Standard deviation of the points' noise along the local surface normal. */
  double level = 0.0;
  /** The surface's point spacing, 1 / sqrt(points per unit area): unlike the mean k-NN
   *  distance, it does not grow with the noise. 0 when it cannot be measured. */
  double spacing = 0.0;
  /** The raw statistic behind `level`: the median over the sampled points of the
   *  smallest principal standard deviation of the point and its 10 nearest neighbours,
   *  before the correction for the neighbourhood's size. */
  double one_ring = 0.0;
};

/** \brief Robust estimate of the noise level and of the surface spacing.
 *
 *  The plane fitted to a point and its 10 nearest neighbours (a small patch, so that the
 *  surface's detail is not counted as noise) leaves a residual that falls short of the
 *  noise by a factor that depends only on noise / spacing: 0.82 at a tenth of the
 *  spacing, 0.53 at one spacing, 0.34 at two (the neighbours then come from inside the
 *  noise). The spacing is measured from the median number m of points within R = 4 mean
 *  10-NN distances of a point, s = sqrt(pi (R^2 - 1.45 level^2) / m) (the count of a noisy
 *  plane's points in a ball), and the median residual is divided by the factor measured
 *  on noisy planes at that noise / spacing (a fixed table, bench/calibrate_gamma
 *  --noise-table; solved together with the spacing). On noisy planes the level comes
 *  within 3% and the spacing within 2% of the truth up to noise = 5 spacings. At most
 *  20,000 points are sampled, evenly along the rows. Results do not depend on the number
 *  of threads. Level 0 for fewer than 4 points or points all on one spot. */
NoiseEstimate
estimateNoise (const Signal3 &points, int num_threads = 0);

} // namespace core
} // namespace pcl_graph_denoise

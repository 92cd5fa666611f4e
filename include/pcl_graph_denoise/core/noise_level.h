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
   *  distance, it does not grow with the noise. 0 when it was not measured. */
  double spacing = 0.0;
  /** The raw statistic behind `level`: the median over the sampled vertices of the
   *  smallest principal standard deviation of the vertex, its graph neighbours and
   *  theirs (scaled by sqrt(m / (m - 3)) for m points), before the correction below. */
  double two_ring = 0.0;
  /** How much the surface bends within reach of the smoothing, in 1 / the points' unit:
   *  the mean over every vertex of a cloud under 8,000 points, else every (n / 4,000)-th
   *  rounded down (4,000 to 6,000 balls), of
   *  sqrt(max(0, v - level^2)) / R^2, v the smallest principal variance of the points
   *  within R = 6 mean 10-NN distances.
   *  On a sphere of radius r it reads about 1 / (4 sqrt(3) r); on a plane only the
   *  noise's own scatter; detail finer than the ball (a period under about 12 spacings)
   *  it reads by its amplitude only, as gentle bending. Its inverse is the detail length
   *  behind core::detailGammaFactor. 0 when no ball bends above the noise (v <= level^2
   *  in every ball: a plane, or noise of several spacings that buries the bending);
   *  -1 when it was not measured (no ball of 12 points or more). (A second, narrower
   *  ball for fine detail was tried: at 3 spacings the noise's scatter swamps it.) */
  double curvature = -1.0;
};

/** \brief Robust estimate of the noise level, and of the surface spacing it needs.
 *
 *  A plane fitted over a vertex's two graph rings (wide enough to take in noise that is
 *  correlated over a few neighbours, as a range scanner's is) leaves a residual close to
 *  the noise while the noise is small against the point spacing, and short of it when
 *  the noise nears the spacing: the neighbours then come from inside the noise (on noisy
 *  planes, k = 10: 0.98 of the noise at half a spacing, 0.96 at one, 0.81 at two, 0.65 at
 *  three). The spacing is measured from the median number m of points within R = 4 mean
 *  10-NN distances of a point, s = sqrt(pi (R^2 - 1.45 level^2) / m) (the count of a noisy
 *  plane's points in a ball; R is doubled, at most twice, while the level solved with it
 *  exceeds 0.45 R, where noise of several spacings fills the ball), and the median residual is divided by the factor measured
 *  on noisy planes at that noise / spacing (a fixed table, bench/calibrate_gamma
 *  --noise-table; solved together with the spacing). At most 20,000 vertices are sampled,
 *  evenly along the graph's spatial order; `points` are in the graph's vertex order.
 *  Results do not depend on the number of threads. Level 0 for a graph without edges.
 *  \throws std::invalid_argument when points and graph differ in size. */
NoiseEstimate
estimateNoise (const PointGraph &graph, const Signal3 &points, int num_threads = 0);

} // namespace core
} // namespace pcl_graph_denoise

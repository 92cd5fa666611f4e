/*
 * pcl_graph_denoise: graph-signal-processing point cloud denoising for PCL.
 * SPDX-License-Identifier: BSD-3-Clause
 */
#include <pcl_graph_denoise/core/noise_level.h>

#include "neighbor_search.h"
#include "parallel.h"
#include "two_ring.h"

#include <Eigen/Eigenvalues>

#include <algorithm>
#include <array>
#include <cmath>
#include <stdexcept>
#include <utility>
#include <vector>

namespace pcl_graph_denoise {
namespace core {

namespace {

constexpr int kNeighbours = 10;          // for the mean k-NN distance behind the ball
constexpr std::size_t kSamples = 20000;  // a median needs no more
constexpr double kBallRadius = 4.0;      // in mean k-NN distances
/** The ball that counts the points for the spacing is widened (twice as wide, at most
 *  kMaxWidenings times) while the noise level solved with it exceeds this fraction of its
 *  radius: the count of a noisy plane's points in the ball, pi (R^2 - 1.45 level^2) per
 *  unit area, holds while the ball reaches well past the noise, and on the noisy planes of
 *  the table below it read the noise 18% high at 6 spacings of noise (the level then
 *  0.56 R) and pinned it at the table's last row beyond; with the ball widened where the
 *  level exceeds 0.45 R (noise above about 4.5 spacings) it reads within 5% up to 8
 *  spacings, 9% low at 10 and 19% low at 16 (the count model's own bias). */
constexpr double kWidenAt = 0.45;
constexpr int kMaxWidenings = 2;
constexpr std::size_t kCurvatureSamples = 4000;  // a mean needs no more
constexpr double kCurvatureRadius = 6.0;         // in mean k-NN distances
constexpr std::size_t kCurvatureMinimumBall = 12;

/** Median two-ring residual / spacing on noisy planes (160,000 points, k = 10, three
 *  seeds; bench/calibrate_gamma --noise-table), against noise / spacing. */
struct Saturation
{
  double noise_over_spacing;
  double residual_over_spacing;
};
constexpr std::array<Saturation, 18> kSaturation = {{
    {0.0, 0.0},
    {0.1, 0.0989},
    {0.25, 0.2463},
    {0.5, 0.4890},
    {0.75, 0.7301},
    {1.0, 0.9596},
    {1.25, 1.1688},
    {1.5, 1.3457},
    {2.0, 1.6123},
    {2.5, 1.8002},
    {3.0, 1.9556},
    {4.0, 2.1993},
    {5.0, 2.3932},
    {6.0, 2.5473},
    {8.0, 2.7940},
    {10.0, 2.9936},
    {12.0, 3.1776},
    {16.0, 3.4926},
}};

/** noise / spacing for a median residual / spacing, by the table (linear between its
 *  rows, capped at its last row). */
double
noiseOverSpacing (double residual_over_spacing)
{
  for (std::size_t i = 1; i < kSaturation.size (); ++i)
  {
    const Saturation &a = kSaturation[i - 1], &b = kSaturation[i];
    if (residual_over_spacing <= b.residual_over_spacing)
      return a.noise_over_spacing + (b.noise_over_spacing - a.noise_over_spacing) *
                                        (residual_over_spacing - a.residual_over_spacing) /
                                        (b.residual_over_spacing - a.residual_over_spacing);
  }
  return kSaturation.back ().noise_over_spacing;
}

double
median (std::vector<double> values)
{
  const std::size_t mid = values.size () / 2;
  std::nth_element (values.begin (), values.begin () + mid, values.end ());
  return values[mid];
}

/** The ball that counts a surface's points for its spacing: its radius and the median
 *  count of points within it. */
struct SpacingBall
{
  double radius;
  double count;

  /** The spacing the count gives with noise `level`: a noisy plane holds about
   *  pi (R^2 - 1.45 level^2) / spacing^2 points in the ball (its area held at a quarter of
   *  the ball's section at least). */
  double
  spacingAt (double level) const
  {
    return std::sqrt (M_PI * std::max (radius * radius - 1.45 * level * level, 0.25 * radius * radius) /
                      count);
  }
};

/** The noise level that solves level = ratio (two_ring / spacing (level)) x spacing (level)
 *  with the ball's spacing. The right side minus the left is positive at 0 and may cross
 *  zero more than once where the table is flat (the spacing shrinks as the level grows):
 *  the first crossing, found by a scan and then bisected, is the one continuous with low
 *  noise; the level where the ball's area reaches its floor when there is none below. */
double
solveLevel (double two_ring, const SpacingBall &ball)
{
  const auto excess = [&] (double at) {
    const double s = ball.spacingAt (at);
    return noiseOverSpacing (two_ring / s) * s - at;
  };
  const double top = ball.radius * std::sqrt (0.75 / 1.45);  // the area's floor
  constexpr int kScan = 256;
  double low = top, high = top;
  for (int step = 1; step <= kScan; ++step)
  {
    const double at = top * step / kScan;
    if (excess (at) <= 0.0)
    {
      low = top * (step - 1) / kScan, high = at;
      break;
    }
  }
  for (int step = 0; step < 60 && high - low > 1e-9 * high; ++step)
  {
    const double mid = 0.5 * (low + high);
    (excess (mid) > 0.0 ? low : high) = mid;
  }
  return 0.5 * (low + high);
}

/** The mean over every (n / kCurvatureSamples)-th point, rounded down (every point when
 *  n < 2 kCurvatureSamples; else kCurvatureSamples to 1.5 times that), of how far the
 *  surface within `radius` of the point bends away from a plane, beyond the noise:
 *  sqrt(max(0, smallest principal variance of the ball - level^2)) / radius^2 (on a
 *  sphere of radius R, 1 / (4 sqrt(3) R): heights r^2 / 2R over a uniform disc); balls
 *  of fewer than kCurvatureMinimumBall points do not count. -1 when no ball counts (not
 *  measured). */
double
meanBending (const detail::KdTree &tree, const Signal3 &points, double radius, double level,
             int num_threads)
{
  const std::size_t n = static_cast<std::size_t> (points.rows ());
  if (!(radius > 0.0) || !std::isfinite (radius))
    return -1.0;
  const std::size_t stride = std::max<std::size_t> (1, n / kCurvatureSamples);
  const std::size_t samples = (n + stride - 1) / stride;
  std::vector<double> bending (samples, -1.0);
  detail::parallelFor (samples, num_threads, [&] (std::size_t begin, std::size_t end) {
    std::vector<VertexIndex> within;
    std::vector<std::pair<VertexIndex, float>> scratch;
    for (std::size_t sample = begin; sample < end; ++sample)
    {
      const std::size_t i = sample * stride;
      within.clear ();
      tree.othersWithin (static_cast<VertexIndex> (i), static_cast<float> (radius), within, scratch);
      within.push_back (static_cast<VertexIndex> (i));
      if (within.size () < kCurvatureMinimumBall)
        continue;
      Eigen::Vector3d mean = Eigen::Vector3d::Zero ();
      for (VertexIndex j : within)
        mean += points.row (j).transpose ();
      mean /= double (within.size ());
      Eigen::Matrix3d covariance = Eigen::Matrix3d::Zero ();
      for (VertexIndex j : within)
      {
        const Eigen::Vector3d d = points.row (j).transpose () - mean;
        covariance.noalias () += d * d.transpose ();
      }
      covariance /= double (within.size ());
      Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig;
      eig.computeDirect (covariance, Eigen::EigenvaluesOnly);
      bending[sample] = std::sqrt (std::max (0.0, eig.eigenvalues () (0) - level * level)) /
                        (radius * radius);
    }
  });
  double sum = 0.0;
  std::size_t counted = 0;
  for (double b : bending)
    if (b >= 0.0)
      sum += b, ++counted;
  return counted > 0 ? sum / double (counted) : -1.0;
}

} // namespace

NoiseEstimate
estimateNoise (const PointGraph &graph, const Signal3 &points, int num_threads)
{
  NoiseEstimate estimate;
  const std::size_t n = graph.numVertices ();
  if (static_cast<std::size_t> (points.rows ()) != n)
    throw std::invalid_argument ("estimateNoise: points of the wrong size");
  if (n < 4 || graph.numEntries () == 0)
    return estimate;
  const PointMatrix cloud = points.cast<float> ();
  const detail::KdTree tree (cloud);
  const int k = static_cast<int> (std::min<std::size_t> (kNeighbours, n - 1));
  const std::size_t stride = std::max<std::size_t> (1, n / kSamples);
  const std::size_t samples = (n + stride - 1) / stride;

  // The plane through each sampled vertex, its neighbours and theirs, and the vertex's
  // mean distance to its 10 nearest points.
  std::vector<double> residual (samples, -1.0), mean_distance (samples);
  detail::parallelFor (samples, num_threads, [&] (std::size_t begin, std::size_t end) {
    std::vector<VertexIndex> ring, idx (k), scratch_idx;
    std::vector<float> d2 (k), scratch_d2;
    detail::TwoRing two_ring;
    for (std::size_t sample = begin; sample < end; ++sample)
    {
      const std::size_t i = sample * stride;
      tree.nearestOthers (static_cast<VertexIndex> (i), k, idx.data (), d2.data (), scratch_idx, scratch_d2);
      double distance = 0.0;
      for (int m = 0; m < k; ++m)
        distance += std::sqrt (double (d2[m]));
      mean_distance[sample] = distance / k;
      two_ring.collect (graph, i, ring);
      const double m = double (ring.size ());
      if (m < 5.0)
        continue;  // a plane through fewer than five points says nothing of the noise
      const Eigen::Matrix3d covariance = detail::ringCovariance (points, ring, i);
      Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig;
      eig.computeDirect (covariance, Eigen::EigenvaluesOnly);
      residual[sample] = std::sqrt (std::max (0.0, eig.eigenvalues () (0)) * m / (m - 3.0));
    }
  });
  residual.erase (std::remove (residual.begin (), residual.end (), -1.0), residual.end ());
  if (residual.empty ())
    return estimate;
  estimate.two_ring = median (residual);
  const double knn_spacing = detail::meanSpacing (mean_distance);

  // The level at a noise small against the spacing: the fallback when no spacing can be
  // measured.
  const double low_noise_ratio = kSaturation[1].residual_over_spacing / kSaturation[1].noise_over_spacing;
  estimate.level = estimate.two_ring / low_noise_ratio;
  const double first_radius = kBallRadius * knn_spacing;
  if (!(first_radius > 0.0) || !std::isfinite (first_radius))
    return estimate;

  // The level with the count of the ball of the first radius, then of a ball twice as wide
  // while the level fills it (kWidenAt).
  std::vector<double> count (samples);
  SpacingBall ball{first_radius, 0.0};
  double level = 0.0;
  for (int widening = 0;; ++widening)
  {
    detail::parallelFor (samples, num_threads, [&] (std::size_t begin, std::size_t end) {
      std::vector<VertexIndex> within;
      std::vector<std::pair<VertexIndex, float>> scratch;
      for (std::size_t sample = begin; sample < end; ++sample)
      {
        within.clear ();
        tree.othersWithin (static_cast<VertexIndex> (sample * stride),
                           static_cast<float> (ball.radius), within, scratch);
        count[sample] = double (within.size () + 1);
      }
    });
    ball.count = median (count);
    level = solveLevel (estimate.two_ring, ball);
    if (level <= kWidenAt * ball.radius || widening == kMaxWidenings)
      break;
    ball.radius *= 2.0;
  }
  const double spacing = ball.spacingAt (level);
  estimate.level = level;
  estimate.spacing = spacing;
  estimate.curvature =
      meanBending (tree, points, kCurvatureRadius * knn_spacing, level, num_threads);
  return estimate;
}

} // namespace core
} // namespace pcl_graph_denoise

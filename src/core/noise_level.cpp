/*
 * pcl_graph_denoise: graph-signal-processing point cloud denoising for PCL.
 * SPDX-License-Identifier: BSD-3-Clause
 */
#include <pcl_graph_denoise/core/noise_level.h>

#include "two_ring.h"
#include "parallel.h"

#include <Eigen/Eigenvalues>

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <vector>

namespace pcl_graph_denoise {
namespace core {

double
estimateNoiseLevel (const PointGraph &graph, const Signal3 &points, int num_threads)
{
  const std::size_t n = graph.numVertices ();
  if (static_cast<std::size_t> (points.rows ()) != n)
    throw std::invalid_argument ("estimateNoiseLevel: points of the wrong size");
  // A median needs no more than a sample: every stride-th vertex, at most kSamples of
  // them, spread over the cloud by the graph's spatial order.
  constexpr std::size_t kSamples = 20000;
  const std::size_t stride = std::max<std::size_t> (1, n / kSamples);
  const std::size_t samples = (n + stride - 1) / stride;
  std::vector<double> deviation (samples, -1.0);
  detail::parallelFor (samples, num_threads, [&] (std::size_t begin, std::size_t end) {
    std::vector<VertexIndex> ring;
    detail::TwoRing two_ring;
    for (std::size_t sample = begin; sample < end; ++sample)
    {
      const std::size_t i = sample * stride;
      // The vertex, its neighbours and theirs: wide enough that noise comparable to
      // the spacing does not hide in the choice of the neighbourhood.
      two_ring.collect (graph, i, ring);
      const double m = double (ring.size ());
      if (m < 5.0)
        continue;  // a plane through fewer than five points says nothing of the noise
      const Eigen::Matrix3d covariance = detail::ringCovariance (points, ring, i);
      Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig;
      eig.computeDirect (covariance, Eigen::EigenvaluesOnly);
      const double smallest = std::max (0.0, eig.eigenvalues () (0));
      deviation[sample] = std::sqrt (smallest * m / (m - 3.0));
    }
  });
  deviation.erase (std::remove (deviation.begin (), deviation.end (), -1.0), deviation.end ());
  if (deviation.empty ())
    return 0.0;
  const std::size_t mid = deviation.size () / 2;
  std::nth_element (deviation.begin (), deviation.begin () + mid, deviation.end ());
  return deviation[mid];
}

} // namespace core
} // namespace pcl_graph_denoise

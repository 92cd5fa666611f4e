/*
 * pcl_graph_denoise: graph-signal-processing point cloud denoising for PCL.
 * SPDX-License-Identifier: BSD-3-Clause
 */
#include <pcl_graph_denoise/core/normals.h>

#include "two_ring.h"
#include "parallel.h"

#include <Eigen/Eigenvalues>

#include <stdexcept>

namespace pcl_graph_denoise {
namespace core {

Signal3
estimateNormals (const PointGraph &graph, const Signal3 &points, int num_threads)
{
  const std::size_t n = graph.numVertices ();
  if (static_cast<std::size_t> (points.rows ()) != n)
    throw std::invalid_argument ("estimateNormals: points of the wrong size");
  Signal3 normals = Signal3::Zero (static_cast<Eigen::Index> (n), 3);
  detail::parallelFor (n, num_threads, [&] (std::size_t begin, std::size_t end) {
    std::vector<VertexIndex> ring;
    detail::TwoRing two_ring;
    Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig;
    for (std::size_t i = begin; i < end; ++i)
    {
      two_ring.collect (graph, i, ring);
      if (ring.size () < 3)
        continue;
      eig.computeDirect (detail::ringCovariance (points, ring, i));
      normals.row (i) = eig.eigenvectors ().col (0).transpose ();
    }
  });
  return normals;
}

Signal3
normalDisplacement (const Signal3 &f, const Signal3 &x, const Signal3 &normals)
{
  if (x.rows () != f.rows () || normals.rows () != f.rows ())
    throw std::invalid_argument ("normalDisplacement: signals of different sizes");
  Signal3 out (f.rows (), 3);
  for (Eigen::Index i = 0; i < f.rows (); ++i)
    out.row (i) = f.row (i) + (x.row (i) - f.row (i)).dot (normals.row (i)) * normals.row (i);
  return out;
}

} // namespace core
} // namespace pcl_graph_denoise

/*
 * pcl_graph_denoise: graph-signal-processing point cloud denoising for PCL.
 * SPDX-License-Identifier: BSD-3-Clause
 */
#include <pcl_graph_denoise/core/normals.h>

#include "two_ring.h"
#include "parallel.h"

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>

#include <algorithm>
#include <cmath>

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

namespace {

constexpr std::size_t kQuadricMinimumRing = 10;  // 6 coefficients, with some redundancy
constexpr int kRobustIterations = 4;

using Basis = Eigen::Matrix<double, 6, 1>;

/** The quadric's basis at tangential coordinates (a, b), already divided by the patch
 *  radius so that the normal equations stay well conditioned at any scale. */
inline Basis
quadricBasis (double a, double b)
{
  Basis phi;
  phi << a * a, a * b, b * b, a, b, 1.0;
  return phi;
}

} // namespace

Signal3
quadricDisplacement (const PointGraph &graph, const Signal3 &f, const Signal3 &x, double noise,
                     int num_threads)
{
  const std::size_t n = graph.numVertices ();
  if (static_cast<std::size_t> (f.rows ()) != n || static_cast<std::size_t> (x.rows ()) != n)
    throw std::invalid_argument ("quadricDisplacement: signals of the wrong size");
  const bool robust = std::isfinite (noise) && noise > 0.0;
  Signal3 out = x;
  detail::parallelFor (n, num_threads, [&] (std::size_t begin, std::size_t end) {
    std::vector<VertexIndex> ring;
    std::vector<Basis> phi;
    std::vector<double> height, weight;
    detail::TwoRing two_ring;
    Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig;
    Eigen::LDLT<Eigen::Matrix<double, 6, 6>> ldlt;
    for (std::size_t i = begin; i < end; ++i)
    {
      two_ring.collect (graph, i, ring);
      if (ring.size () < 3)
        continue;
      eig.computeDirect (detail::ringCovariance (x, ring, i));
      const Eigen::Vector3d normal = eig.eigenvectors ().col (0);
      const Eigen::Vector3d origin = x.row (i).transpose ();
      const Eigen::Vector3d from_f = f.row (i).transpose () - origin;
      const double f_height = from_f.dot (normal);
      const double radius = std::sqrt (eig.eigenvalues ()(2) + eig.eigenvalues ()(1));
      if (ring.size () < kQuadricMinimumRing || !(radius > 0.0))
      {
        out.row (i) = f.row (i) - f_height * normal.transpose ();  // the plane through x_i
        continue;
      }
      const Eigen::Vector3d u = eig.eigenvectors ().col (2) / radius;
      const Eigen::Vector3d v = eig.eigenvectors ().col (1) / radius;
      phi.resize (ring.size ());
      height.resize (ring.size ());
      weight.assign (ring.size (), 1.0);
      double support = 0.0;  // the patch's largest tangential distance (squared)
      for (std::size_t r = 0; r < ring.size (); ++r)
      {
        const Eigen::Vector3d d = (x.row (ring[r])).transpose () - origin;
        const double a = d.dot (u), b = d.dot (v);
        phi[r] = quadricBasis (a, b);
        height[r] = d.dot (normal);
        support = std::max (support, a * a + b * b);
      }
      Basis q = Basis::Zero ();
      bool fitted = false;
      // Robust: the first weights come from the plane through x_i (q = 0), so that a
      // point between two sheets starts on its own side.
      for (int iteration = 0; iteration < (robust ? kRobustIterations : 1); ++iteration)
      {
        if (robust)
          for (std::size_t r = 0; r < ring.size (); ++r)
          {
            const double t = (height[r] - phi[r].dot (q)) / noise;
            weight[r] = std::exp (-0.5 * t * t);
          }
        Eigen::Matrix<double, 6, 6> normal_matrix = Eigen::Matrix<double, 6, 6>::Zero ();
        Basis rhs = Basis::Zero ();
        for (std::size_t r = 0; r < ring.size (); ++r)
        {
          // The full outer product: a fixed 6 x 6 that Eigen unrolls, several times
          // faster than its generic rank update of a triangle.
          normal_matrix.noalias () += (weight[r] * phi[r]) * phi[r].transpose ();
          rhs += weight[r] * height[r] * phi[r];
        }
        ldlt.compute (normal_matrix);
        if (ldlt.info () != Eigen::Success || !(ldlt.rcond () > 1e-10))
          break;  // too few points keep weight: keep the last fit
        const Basis solved = ldlt.solve (rhs);
        if (!solved.allFinite ())
          break;
        q = solved;
        fitted = true;
      }
      // The quadric is evaluated where f_i projects, pulled back onto the patch when it
      // lies outside: a patch much smaller than f_i's distance to x_i (the points of a
      // piecewise-constant TV estimate, collapsed together) must not be extrapolated.
      double fa = from_f.dot (u), fb = from_f.dot (v);
      const double reach = fa * fa + fb * fb;
      if (reach > support)
      {
        const double pull = support > 0.0 ? std::sqrt (support / reach) : 0.0;
        fa *= pull;
        fb *= pull;
      }
      const double target = fitted ? quadricBasis (fa, fb).dot (q) : 0.0;  // else the plane
      // And with a noise level, the move along the normal stays within the smoothing's
      // own move plus three noise levels: a fit that still goes astray cannot throw the
      // point away.
      double move = target - f_height;
      if (robust)
      {
        const double limit = from_f.norm () + 3.0 * noise;
        move = std::clamp (move, -limit, limit);
      }
      out.row (i) = f.row (i) + move * normal.transpose ();
    }
  });
  return out;
}

} // namespace core
} // namespace pcl_graph_denoise

/*
 * pcl_graph_denoise: graph-signal-processing point cloud denoising for PCL.
 * SPDX-License-Identifier: BSD-3-Clause
 */
#pragma once

/* A vertex's local surface patch on the graph: its two rings of neighbours and their
 * covariance (the local plane fit behind the noise estimate and the normals). */

#include <pcl_graph_denoise/core/graph.h>

#include <Eigen/Core>

#include <algorithm>
#include <vector>

namespace pcl_graph_denoise {
namespace core {
namespace detail {

/** The vertex i, its neighbours and theirs, sorted, each once. */
inline void
twoRing (const PointGraph &graph, std::size_t i, std::vector<VertexIndex> &ring)
{
  ring.clear ();
  ring.push_back (static_cast<VertexIndex> (i));
  for (std::uint64_t e = graph.row_ptr[i]; e < graph.row_ptr[i + 1]; ++e)
  {
    const VertexIndex j = graph.col[e];
    ring.push_back (j);
    for (std::uint64_t f = graph.row_ptr[j]; f < graph.row_ptr[j + 1]; ++f)
      ring.push_back (graph.col[f]);
  }
  std::sort (ring.begin (), ring.end ());
  ring.erase (std::unique (ring.begin (), ring.end ()), ring.end ());
}

/** Covariance of the points of `ring` (taken relative to the point `origin`, so that
 *  large coordinates lose no precision). */
inline Eigen::Matrix3d
ringCovariance (const Signal3 &points, const std::vector<VertexIndex> &ring, std::size_t origin)
{
  const double m = double (ring.size ());
  Eigen::Vector3d mean = Eigen::Vector3d::Zero ();
  Eigen::Matrix3d second = Eigen::Matrix3d::Zero ();
  for (const VertexIndex j : ring)
  {
    const Eigen::Vector3d d = (points.row (j) - points.row (origin)).transpose ();
    mean += d;
    second += d * d.transpose ();
  }
  mean /= m;
  return second / m - mean * mean.transpose ();
}

} // namespace detail
} // namespace core
} // namespace pcl_graph_denoise

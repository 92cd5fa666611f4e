/*
 * pcl_graph_denoise: graph-signal-processing point cloud denoising for PCL.
 * SPDX-License-Identifier: BSD-3-Clause
 */
#pragma once

/* Private to the core: exact nearest-neighbour queries through nanoflann.
 * nanoflann was measured against PCL's KdTreeFLANN on the same Morton-ordered
 * points and threads and kept as the faster (see bench/bench_graph.cpp). */

#include <pcl_graph_denoise/core/graph.h>

#include <memory>
#include <utility>

namespace pcl_graph_denoise {
namespace core {
namespace detail {

/** A k-d tree over the rows of a point matrix (which must outlive it). Queries are
 *  const and may run concurrently. */
class KdTree
{
public:
  explicit KdTree (const PointMatrix &points);
  ~KdTree ();
  KdTree (const KdTree &) = delete;
  KdTree &
  operator= (const KdTree &) = delete;

  /** The k nearest other points of point `self` (self excluded even among duplicates
   *  at distance zero), nearest first: writes k indices and squared distances. Needs
   *  k < number of points. */
  void
  nearestOthers (VertexIndex self, int k, VertexIndex *indices, float *squared_distances,
                 std::vector<VertexIndex> &scratch_idx, std::vector<float> &scratch_d2) const;

  /** The min(k, number of points) nearest points of the tree to `query` (x, y, z),
   *  nearest first: writes their indices and squared distances; returns the count. */
  std::size_t
  nearest (const float *query, int k, VertexIndex *indices, float *squared_distances) const;

  /** Every other point closer than `radius` to point `self`, appended
   *  to `neighbors` in no particular order. */
  void
  othersWithin (VertexIndex self, float radius, std::vector<VertexIndex> &neighbors,
                std::vector<std::pair<VertexIndex, float>> &scratch) const;

private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

} // namespace detail
} // namespace core
} // namespace pcl_graph_denoise

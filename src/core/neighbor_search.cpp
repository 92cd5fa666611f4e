/*
 * pcl_graph_denoise: graph-signal-processing point cloud denoising for PCL.
 * SPDX-License-Identifier: BSD-3-Clause
 */
#include "neighbor_search.h"

// Among equidistant candidates keep the lowest index: ties resolve the same way
// as a brute-force search sorted by (distance, index).
#define NANOFLANN_FIRST_MATCH
#include <nanoflann.hpp>

#include <algorithm>

namespace pcl_graph_denoise {
namespace core {
namespace detail {

namespace {

/** nanoflann dataset adaptor over a row-major N x 3 float matrix. */
struct MatrixDataset
{
  const PointMatrix &points;

  std::size_t
  kdtree_get_point_count () const { return static_cast<std::size_t> (points.rows ()); }

  float
  kdtree_get_pt (std::size_t i, std::size_t d) const { return points (i, d); }

  template <typename BoundingBox>
  bool
  kdtree_get_bbox (BoundingBox &) const { return false; }
};

using Tree = nanoflann::KDTreeSingleIndexAdaptor<
    nanoflann::L2_Simple_Adaptor<float, MatrixDataset, float, VertexIndex>, MatrixDataset, 3,
    VertexIndex>;

} // namespace

struct KdTree::Impl
{
  explicit Impl (const PointMatrix &p)
  : data{p}, tree (3, data, nanoflann::KDTreeSingleIndexAdaptorParams (16))
  {}
  MatrixDataset data;
  Tree tree;
};

KdTree::KdTree (const PointMatrix &points) : impl_ (new Impl (points)) {}

KdTree::~KdTree () = default;

void
KdTree::nearestOthers (VertexIndex self, int k, VertexIndex *indices, float *squared_distances,
                       std::vector<VertexIndex> &scratch_idx,
                       std::vector<float> &scratch_d2) const
{
  const std::size_t wanted = static_cast<std::size_t> (k) + 1;
  scratch_idx.resize (wanted);
  scratch_d2.resize (wanted);
  const float *query = impl_->data.points.row (self).data ();
  const std::size_t found =
      impl_->tree.knnSearch (query, wanted, scratch_idx.data (), scratch_d2.data ());
  // Drop the query itself; among duplicates it may be missing, then drop the farthest.
  std::size_t out = 0;
  bool skipped = false;
  for (std::size_t m = 0; m < found && out < static_cast<std::size_t> (k); ++m)
  {
    if (!skipped && scratch_idx[m] == self)
    {
      skipped = true;
      continue;
    }
    indices[out] = scratch_idx[m];
    squared_distances[out] = scratch_d2[m];
    ++out;
  }
}

std::size_t
KdTree::nearest (const float *query, int k, VertexIndex *indices, float *squared_distances) const
{
  const std::size_t wanted =
      std::min (static_cast<std::size_t> (k), impl_->data.kdtree_get_point_count ());
  if (wanted == 0)
    return 0;
  return impl_->tree.knnSearch (query, wanted, indices, squared_distances);
}

void
KdTree::othersWithin (VertexIndex self, float radius, std::vector<VertexIndex> &neighbors,
                      std::vector<std::pair<VertexIndex, float>> &scratch) const
{
  scratch.clear ();
  const float *query = impl_->data.points.row (self).data ();
  // nanoflann's L2 radius is squared and strict: points closer than `radius`.
  impl_->tree.radiusSearch (query, radius * radius, scratch,
                            nanoflann::SearchParams (32, 0.0f, false));
  for (const auto &hit : scratch)
    if (hit.first != self)
      neighbors.push_back (hit.first);
}

} // namespace detail
} // namespace core
} // namespace pcl_graph_denoise

/*
 * pcl_graph_denoise: graph-signal-processing point cloud denoising for PCL.
 * SPDX-License-Identifier: BSD-3-Clause
 */
#pragma once

/* Private to the core: exact nearest-neighbour queries, through nanoflann one query at
 * a time (nanoflann was measured against PCL's KdTreeFLANN on the same Morton-ordered
 * points and threads and kept as the faster), and every point's neighbours at once on
 * the cells of the Morton curve (allNearestOthers, faster still: bench/bench_graph.cpp). */

#include <pcl_graph_denoise/core/graph.h>

#include "spatial_order.h"

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

  /** The k nearest other points of point `self` (k < number of points) by (squared
   *  distance, index), nearest first, exactly (nearestOthers keeps any of the points tied
   *  at the k-th distance); returns the mean of their distances. `scratch`: any vector,
   *  reused between calls. */
  double
  nearestOthersExact (VertexIndex self, int k, VertexIndex *indices,
                      std::vector<std::uint64_t> &scratch) const;

  /** Every other point closer than `radius` to point `self`, appended
   *  to `neighbors` in no particular order. */
  void
  othersWithin (VertexIndex self, float radius, std::vector<VertexIndex> &neighbors,
                std::vector<std::pair<VertexIndex, float>> &scratch) const;

private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

/** How allNearestOthers found each point's neighbours. */
struct NearestOthersPaths
{
  std::size_t grid = 0;      ///< on the grid of its level
  std::size_t coarser = 0;   ///< on a coarser grid
  std::size_t scanned = 0;   ///< compared with every point
  std::size_t tree = 0;      ///< in the k-d tree
};

/** The k nearest other points of every point (k < number of points), by (squared
 *  distance in single precision, index), so that ties go to the lower index: row v of
 *  `indices` (n x k, row-major) for point v, nearest first, and the mean of their
 *  distances in `mean_distances[v]`. `points` are in the order of `sorted` (row v has
 *  code sorted.codes[v]).
 *
 *  Each point is compared with the points of the 27 cells around its own at one level
 *  of the curve's octree, nearest cells first while they can still hold one of its k
 *  nearest (the level: the finest at which half the points lie in cells of at least
 *  max(4, 2k) points). Points whose k-th neighbour may lie beyond those cells are searched
 *  again on the grids of up to two coarser levels (cells twice and four times as wide).
 *  The points left, in crowded cells (many copies, or a few far outliers stretching the
 *  grid) or still unsettled, are compared with every point when there are at most 16 of
 *  them, else searched in a k-d tree. `paths`, when given, receives how many points each
 *  way settled. Does not depend on the number of threads. */
void
allNearestOthers (const PointMatrix &points, const MortonSort &sorted, int k, int num_threads,
                  VertexIndex *indices, double *mean_distances,
                  NearestOthersPaths *paths = nullptr);

/** The spacing of a cloud: the mean of its points' mean distances to their nearest
 *  others (`means`), without the points whose own exceeds 50 times the median's, whose
 *  distances tell nothing of the sampling (one point 1,000 units away from a grid spaced
 *  0.01 apart made the plain mean 75 times the grid's). The plain mean, to the bit, where
 *  no point is that far; 0 for none. */
double
meanSpacing (const std::vector<double> &means);

} // namespace detail
} // namespace core
} // namespace pcl_graph_denoise

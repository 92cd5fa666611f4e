/*
 * pcl_graph_denoise: graph-signal-processing point cloud denoising for PCL.
 * SPDX-License-Identifier: BSD-3-Clause
 */
#pragma once

/* A vertex's local surface patch on the graph: its two rings of neighbours and their
 * covariance (the local plane fit behind the noise estimate and the normals). The
 * rings are collected in a reused hash set: sorting them cost two thirds of the normals'
 * time at 1M points. */

#include <pcl_graph_denoise/core/graph.h>

#include <Eigen/Core>

#include <algorithm>
#include <cstdint>
#include <vector>

namespace pcl_graph_denoise {
namespace core {
namespace detail {

/** Collects a vertex's two rings (the vertex, its neighbours and theirs, each once, in
 *  the order first met), and on demand the next ring, with a small open-addressing set
 *  that is reused from vertex to vertex: no sort, no clearing. One per thread.
 *
 *  On dense graphs (a large k, or k >= N: every point linked to all others) a ring's cost
 *  grows with the square of the degree, so that the patches of a cloud took time cubic in
 *  its size. Two limits keep it linear in the degree: a next ring that would mean scanning
 *  more than kScanLimit stored entries is not added (the ring stays as it is), and a vertex
 *  with more than kMaxOneRing neighbours keeps its kMaxOneRing nearest (largest weights,
 *  ties by vertex number) as its ring. Neither is reached by k-NN graphs up to k = 60. */
class TwoRing
{
public:
  /** The most stored entries scanned to add a ring. */
  static constexpr std::uint64_t kScanLimit = 65536;
  /** The most neighbours a ring takes from a vertex's own row. */
  static constexpr std::size_t kMaxOneRing = 1024;

  void
  collect (const PointGraph &graph, std::size_t i, std::vector<VertexIndex> &ring)
  {
    const std::uint64_t first = graph.row_ptr[i], last = graph.row_ptr[i + 1];
    if (last - first > kMaxOneRing)
    {
      nearest_.resize (last - first);
      for (std::uint64_t e = first; e < last; ++e)
        nearest_[e - first] = e;
      const auto closer = [&] (std::uint64_t a, std::uint64_t b) {
        return graph.weight[a] != graph.weight[b] ? graph.weight[a] > graph.weight[b]
                                                  : graph.col[a] < graph.col[b];
      };
      std::nth_element (nearest_.begin (), nearest_.begin () + kMaxOneRing, nearest_.end (),
                        closer);
      nearest_.resize (kMaxOneRing);
      std::sort (nearest_.begin (), nearest_.end ());  // in the row's order
      reset (kMaxOneRing + 1);
      ring.clear ();
      insert (static_cast<VertexIndex> (i), ring);
      for (const std::uint64_t e : nearest_)
        insert (graph.col[e], ring);
      return;
    }
    std::uint64_t bound = 1;
    for (std::uint64_t e = first; e < last; ++e)
    {
      const VertexIndex j = graph.col[e];
      bound += 1 + (graph.row_ptr[j + 1] - graph.row_ptr[j]);
    }
    const bool second = bound <= kScanLimit;
    reset (second ? bound : 1 + (last - first));
    ring.clear ();
    insert (static_cast<VertexIndex> (i), ring);
    for (std::uint64_t e = first; e < last; ++e)
    {
      const VertexIndex j = graph.col[e];
      insert (j, ring);
      if (second)
        for (std::uint64_t f = graph.row_ptr[j]; f < graph.row_ptr[j + 1]; ++f)
          insert (graph.col[f], ring);
    }
  }

  /** Adds the next ring to `ring` as collect left it: the neighbours of every vertex in
   *  it that are not in it yet, in the order first met (after collect, the three rings).
   *  Returns false, and leaves the ring as it is, when that would scan more than
   *  kScanLimit stored entries. */
  bool
  grow (const PointGraph &graph, std::vector<VertexIndex> &ring)
  {
    std::uint64_t bound = 0;
    for (const VertexIndex j : ring)
      bound += 1 + (graph.row_ptr[j + 1] - graph.row_ptr[j]);
    if (bound > kScanLimit)
      return false;
    int bits = bits_;
    while ((std::uint64_t (1) << bits) < 2 * bound)
      ++bits;
    if (bits > bits_)  // a larger table: every vertex of the ring again
    {
      bits_ = bits;
      slot_.assign (std::size_t (1) << bits, 0);
      stamp_.assign (std::size_t (1) << bits, 0);
      epoch_ = 1;
      const std::size_t size = ring.size ();
      for (std::size_t r = 0; r < size; ++r)
        mark (ring[r]);
    }
    const std::size_t size = ring.size ();
    for (std::size_t r = 0; r < size; ++r)
    {
      const VertexIndex j = ring[r];
      for (std::uint64_t e = graph.row_ptr[j]; e < graph.row_ptr[j + 1]; ++e)
        insert (graph.col[e], ring);
    }
    return true;
  }

private:
  /** A fresh (empty) set with room for `bound` vertices. The table only ever grows: a
   *  vertex's three rings need a larger one than the next vertex's two, and reallocating
   *  it at every vertex cost more than the lookups. */
  void
  reset (std::uint64_t bound)
  {
    int bits = std::max (bits_, 4);
    while ((std::uint64_t (1) << bits) < 2 * bound)
      ++bits;
    if (bits != bits_)
    {
      bits_ = bits;
      slot_.assign (std::size_t (1) << bits, 0);
      stamp_.assign (std::size_t (1) << bits, 0);
      epoch_ = 0;
    }
    if (++epoch_ == 0)  // wrapped: forget every stamp
    {
      std::fill (stamp_.begin (), stamp_.end (), 0);
      epoch_ = 1;
    }
  }

  /** Puts v in the set; true when it was not there. */
  bool
  mark (VertexIndex v)
  {
    const std::size_t mask = (std::size_t (1) << bits_) - 1;
    for (std::size_t h = std::size_t ((std::uint64_t (v) * 0x9E3779B97F4A7C15ull) >> (64 - bits_)) & mask;;
         h = (h + 1) & mask)
    {
      if (stamp_[h] != epoch_)
      {
        stamp_[h] = epoch_;
        slot_[h] = v;
        return true;
      }
      if (slot_[h] == v)
        return false;
    }
  }

  void
  insert (VertexIndex v, std::vector<VertexIndex> &ring)
  {
    if (mark (v))
      ring.push_back (v);
  }

  int bits_ = 0;
  std::uint32_t epoch_ = 0;
  std::vector<VertexIndex> slot_;
  std::vector<std::uint32_t> stamp_;
  std::vector<std::uint64_t> nearest_;  ///< a dense row's entries, nearest first
};

/** The covariance of a ring's points (taken relative to the point `origin`, so that large
 *  coordinates lose no precision), from running sums that follow the ring as it grows
 *  (TwoRing::grow appends to it): the three rings' covariance after the two rings' adds
 *  only the third ring's points, in the same order of sums as summing them all. */
class RingMoments
{
public:
  explicit RingMoments (std::size_t origin) : origin_ (origin) {}

  /** The covariance of the points of `ring`, whose first points (as many as at the last
   *  call) are the ones summed then; a ring shorter than that is summed afresh. */
  Eigen::Matrix3d
  covariance (const Signal3 &points, const std::vector<VertexIndex> &ring)
  {
    if (ring.size () < count_)
      *this = RingMoments (origin_);
    for (; count_ < ring.size (); ++count_)
    {
      const Eigen::Vector3d d = (points.row (ring[count_]) - points.row (origin_)).transpose ();
      sum_ += d;
      second_ += d * d.transpose ();
    }
    const double m = double (ring.size ());
    const Eigen::Vector3d mean = sum_ / m;
    return second_ / m - mean * mean.transpose ();
  }

private:
  std::size_t origin_;
  std::size_t count_ = 0;
  Eigen::Vector3d sum_ = Eigen::Vector3d::Zero ();
  Eigen::Matrix3d second_ = Eigen::Matrix3d::Zero ();
};

/** Covariance of the points of `ring` (relative to the point `origin`). */
inline Eigen::Matrix3d
ringCovariance (const Signal3 &points, const std::vector<VertexIndex> &ring, std::size_t origin)
{
  return RingMoments (origin).covariance (points, ring);
}

} // namespace detail
} // namespace core
} // namespace pcl_graph_denoise

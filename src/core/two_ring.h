/*
 * pcl_graph_denoise: graph-signal-processing point cloud denoising for PCL.
 * SPDX-License-Identifier: BSD-3-Clause
 */
#pragma once

/* A vertex's local surface patch on the graph: its two rings of neighbours and their
 * covariance (the local plane fit behind the noise estimate and the normals). The
 * rings are collected in reused stamp tables: sorting them cost two thirds of the normals'
 * time at 1M points. */

#include <pcl_graph_denoise/core/graph.h>

#include <Eigen/Core>

#include <algorithm>
#include <array>
#include <cstdint>
#include <vector>

namespace pcl_graph_denoise {
namespace core {
namespace detail {

/** Collects a vertex's two rings (the vertex, its neighbours and theirs, each once, in
 *  the order first met), and on demand the next ring, with stamp tables that are reused
 *  from vertex to vertex: no sort, no clearing. One per thread.
 *
 *  The graph's vertices are in Morton order, so nearly every ring member lies within a
 *  few ten thousand positions of the vertex (at 1M points, 99% of the two-hop entries
 *  within 65,536): those are marked in a window of direct stamps that follows the
 *  vertices along, one load and one store each, without a branch that depends on the
 *  data; the rest go to a small open-addressing hash set. The direct window made the
 *  rings of a 1M-point sphere (two rings of every vertex, three of 40%) 2.6 times
 *  faster than the hash set alone.
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
  /** The vertices the direct window covers (fewer in a smaller graph): 512 KB of
   *  stamps. */
  static constexpr std::size_t kWindow = std::size_t (1) << 17;

  /** `window`: the vertices the direct window covers at most (at least 1); tests take
   *  small ones so that the hash set takes part. */
  explicit TwoRing (std::size_t window = kWindow) : window_limit_ (std::max<std::size_t> (window, 1)) {}

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
      reset (graph, i, kMaxOneRing + 1);
      ring.clear ();
      Appender out (*this, ring, kMaxOneRing + 1);
      out.insert (static_cast<VertexIndex> (i));
      for (const std::uint64_t e : nearest_)
        out.insert (graph.col[e]);
      return;
    }
    std::uint64_t bound = 1;
    for (std::uint64_t e = first; e < last; ++e)
    {
      const VertexIndex j = graph.col[e];
      bound += 1 + (graph.row_ptr[j + 1] - graph.row_ptr[j]);
    }
    const bool second = bound <= kScanLimit;
    if (!second)
      bound = 1 + (last - first);
    reset (graph, i, bound);
    ring.clear ();
    Appender out (*this, ring, bound);
    out.insert (static_cast<VertexIndex> (i));
    for (std::uint64_t e = first; e < last; ++e)
    {
      const VertexIndex j = graph.col[e];
      out.insert (j);
      if (second)
        out.insert (rowBegin (graph, j), rowEnd (graph, j));
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
    if (bits > bits_)  // a larger hash table: every far vertex of the ring again
    {
      bits_ = bits;
      slot_.assign (std::size_t (1) << bits, 0);
      stamp_.assign (std::size_t (1) << bits, 0);
      for (const VertexIndex v : ring)
        if (!inWindow (v))
          markFar (v);
    }
    const std::size_t size = ring.size ();
    Appender out (*this, ring, bound);
    for (std::size_t r = 0; r < size; ++r)
      out.insert (rowBegin (graph, ring[r]), rowEnd (graph, ring[r]));
    return true;
  }

private:
  /** Appends the vertices not yet in the set to a ring: room for `room` more is made
   *  first, each vertex is written and counted only when new, and the ring is cut to
   *  what was counted when the appender goes. */
  class Appender
  {
  public:
    Appender (TwoRing &set, std::vector<VertexIndex> &ring, std::uint64_t room)
      : set_ (set), ring_ (ring), size_ (ring.size ())
    {
      ring_.resize (size_ + room);
    }
    ~Appender () { ring_.resize (size_); }

    inline void
    insert (VertexIndex v)
    {
      ring_[size_] = v;
      size_ += set_.mark (v) ? 1 : 0;
    }

    /** insert for each vertex of [v, last), with the set's state in locals: kept in the
     *  members, it went through memory at every vertex (the stores to the ring and the
     *  stamps may alias them). */
    void
    insert (const VertexIndex *v, const VertexIndex *last)
    {
      VertexIndex *out = ring_.data ();
      std::size_t size = size_;
      std::uint32_t *window = set_.window_.data ();
      const std::size_t base = set_.base_, extent = set_.window_.size ();
      const std::uint32_t epoch = set_.epoch_;
      for (; v != last; ++v)
      {
        const VertexIndex u = *v;
        out[size] = u;
        const std::size_t offset = std::size_t (u) - base;
        if (offset < extent)
        {
          size += window[offset] != epoch ? 1 : 0;
          window[offset] = epoch;
        }
        else
          size += set_.markFar (u) ? 1 : 0;
      }
      size_ = size;
    }

  private:
    TwoRing &set_;
    std::vector<VertexIndex> &ring_;
    std::size_t size_;
  };

  /** The stored neighbours of vertex j, as a range. */
  static const VertexIndex *
  rowBegin (const PointGraph &graph, VertexIndex j) { return graph.col.data () + graph.row_ptr[j]; }
  static const VertexIndex *
  rowEnd (const PointGraph &graph, VertexIndex j) { return graph.col.data () + graph.row_ptr[j + 1]; }

  /** A fresh (empty) set around vertex i, with room for `bound` vertices in its hash
   *  table. The tables only ever grow: a vertex's three rings need a larger one than the
   *  next vertex's two, and reallocating it at every vertex cost more than the lookups. */
  void
  reset (const PointGraph &graph, std::size_t i, std::uint64_t bound)
  {
    const std::size_t size = std::min (window_limit_, graph.numVertices ());
    if (window_.size () != size)  // the first vertex, or another graph
      window_.assign (size, 0);
    // The window is centred again on i once i leaves its middle half; stamps from before
    // are of an earlier epoch, wherever they now fall.
    if (i < base_ + size / 4 || i >= base_ + size - size / 4)
      base_ = std::min (i > size / 2 ? i - size / 2 : 0, graph.numVertices () - size);
    int bits = std::max (bits_, 4);
    while ((std::uint64_t (1) << bits) < 2 * bound)
      ++bits;
    if (bits != bits_)
    {
      bits_ = bits;
      slot_.assign (std::size_t (1) << bits, 0);
      stamp_.assign (std::size_t (1) << bits, 0);
    }
    if (++epoch_ == 0)  // wrapped: forget every stamp
    {
      std::fill (stamp_.begin (), stamp_.end (), 0);
      std::fill (window_.begin (), window_.end (), 0);
      epoch_ = 1;
    }
  }

  inline bool
  inWindow (VertexIndex v) const
  {
    return std::size_t (v) - base_ < window_.size ();  // below base_: wraps, outside
  }

  /** Puts v in the set; true when it was not there. */
  inline bool
  mark (VertexIndex v)
  {
    const std::size_t offset = std::size_t (v) - base_;
    if (offset < window_.size ())
    {
      const bool fresh = window_[offset] != epoch_;
      window_[offset] = epoch_;
      return fresh;
    }
    return markFar (v);
  }

  /** mark for a vertex outside the window, in the hash set. */
  bool
  markFar (VertexIndex v)
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

  std::size_t window_limit_;
  int bits_ = 0;
  /** The current set's stamp; never 0, the stamp of a fresh table. */
  std::uint32_t epoch_ = 0;
  std::vector<VertexIndex> slot_;
  std::vector<std::uint32_t> stamp_;
  /** Direct stamps of the vertices base_ ... base_ + window_.size () - 1. */
  std::vector<std::uint32_t> window_;
  std::size_t base_ = 0;
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
    // The sums in local scalars: kept in the members, each point's update went through
    // memory (they may alias the points) and stalled on its own stores.
    const double o0 = points (origin_, 0), o1 = points (origin_, 1), o2 = points (origin_, 2);
    double s0 = sum_[0], s1 = sum_[1], s2 = sum_[2];
    double m00 = second_[0], m01 = second_[1], m02 = second_[2];
    double m11 = second_[3], m12 = second_[4], m22 = second_[5];
    for (std::size_t r = count_; r < ring.size (); ++r)
    {
      const auto v = static_cast<Eigen::Index> (ring[r]);
      const double d0 = points (v, 0) - o0, d1 = points (v, 1) - o1, d2 = points (v, 2) - o2;
      s0 += d0;
      s1 += d1;
      s2 += d2;
      m00 += d0 * d0;
      m01 += d0 * d1;
      m02 += d0 * d2;
      m11 += d1 * d1;
      m12 += d1 * d2;
      m22 += d2 * d2;
    }
    count_ = ring.size ();
    sum_ = {s0, s1, s2};
    second_ = {m00, m01, m02, m11, m12, m22};
    const double m = double (ring.size ());
    const Eigen::Vector3d mean (s0 / m, s1 / m, s2 / m);
    Eigen::Matrix3d covariance;
    covariance << m00, m01, m02, m01, m11, m12, m02, m12, m22;
    return covariance / m - mean * mean.transpose ();
  }

private:
  std::size_t origin_;
  std::size_t count_ = 0;
  std::array<double, 3> sum_ = {0.0, 0.0, 0.0};
  /** The upper triangle of the sum of d d^T, row by row. */
  std::array<double, 6> second_ = {0.0, 0.0, 0.0, 0.0, 0.0, 0.0};
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

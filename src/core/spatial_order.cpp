/*
 * pcl_graph_denoise: graph-signal-processing point cloud denoising for PCL.
 * SPDX-License-Identifier: BSD-3-Clause
 */
#include "spatial_order.h"

#include "huge_pages.h"
#include "parallel.h"

#include <algorithm>
#include <utility>

namespace pcl_graph_denoise {
namespace core {
namespace detail {

namespace {

/** Spreads the low 21 bits of v so that two zero bits separate consecutive ones. */
std::uint64_t
spreadBits (std::uint64_t v)
{
  v &= 0x1fffffULL;
  v = (v | (v << 32)) & 0x1f00000000ffffULL;
  v = (v | (v << 16)) & 0x1f0000ff0000ffULL;
  v = (v | (v << 8)) & 0x100f00f00f00f00fULL;
  v = (v | (v << 4)) & 0x10c30c30c30c30c3ULL;
  v = (v | (v << 2)) & 0x1249249249249249ULL;
  return v;
}

/** The inverse of spreadBits: every third bit of v, from bit 0, packed. */
std::uint64_t
compactBits (std::uint64_t v)
{
  v &= 0x1249249249249249ULL;
  v = (v | (v >> 2)) & 0x10c30c30c30c30c3ULL;
  v = (v | (v >> 4)) & 0x100f00f00f00f00fULL;
  v = (v | (v >> 8)) & 0x1f0000ff0000ffULL;
  v = (v | (v >> 16)) & 0x1f00000000ffffULL;
  v = (v | (v >> 32)) & 0x1fffffULL;
  return v;
}

} // namespace

std::uint64_t
interleave (std::uint64_t x, std::uint64_t y, std::uint64_t z)
{
  return spreadBits (x) | (spreadBits (y) << 1) | (spreadBits (z) << 2);
}

std::uint64_t
deinterleave (std::uint64_t code, int axis)
{
  return compactBits (code >> axis);
}

std::vector<VertexIndex>
mortonOrder (const PointMatrix &points, int num_threads)
{
  return mortonSort (points, num_threads, false).order;
}

MortonSort
mortonSort (const PointMatrix &points, int num_threads, bool with_codes)
{
  const auto n = static_cast<std::size_t> (points.rows ());
  MortonSort sorted;
  if (n == 0)
    return sorted;

  const Eigen::Vector3f lo = points.colwise ().minCoeff ();
  const Eigen::Vector3f hi = points.colwise ().maxCoeff ();
  const double extent = std::max ({double (hi.x ()) - lo.x (), double (hi.y ()) - lo.y (),
                                   double (hi.z ()) - lo.z ()});
  // One 64-bit key per point: the Morton code above the point's index, so that only
  // the code bits need sorting (ties keep the input order) and items stay 8 bytes.
  int index_bits = 1;
  while (index_bits < 64 && (std::uint64_t (1) << index_bits) < n)
    ++index_bits;
  const int axis_bits = std::min (21, (64 - index_bits) / 3);
  const double cells = double ((std::uint64_t (1) << axis_bits) - 1);
  const double scale = extent > 0.0 ? cells / extent : 0.0;
  sorted.grid.lo = lo.cast<double> ();
  sorted.grid.scale = scale;
  sorted.grid.axis_bits = axis_bits;

  std::vector<std::uint64_t> keys, buffer;
  resizeOnHugePages (keys, n);
  resizeOnHugePages (buffer, n);
  parallelFor (n, num_threads, [&] (std::size_t begin, std::size_t end) {
    for (std::size_t i = begin; i < end; ++i)
    {
      std::uint64_t cell[3];
      for (int d = 0; d < 3; ++d)
        cell[d] = static_cast<std::uint64_t> (
            std::min (cells, (double (points (i, d)) - double (lo (d))) * scale));
      keys[i] = (interleave (cell[0], cell[1], cell[2]) << index_bits) | i;
    }
  });
  // Stable LSD radix sort on the code bits, 11 bits a pass.
  constexpr int kBits = 11;
  constexpr std::size_t kBuckets = std::size_t (1) << kBits;
  const int top = index_bits + 3 * axis_bits;
  std::vector<std::size_t> start (kBuckets + 1);
  for (int shift = index_bits; shift < top; shift += kBits)
  {
    std::fill (start.begin (), start.end (), 0);
    for (const std::uint64_t key : keys)
      ++start[((key >> shift) & (kBuckets - 1)) + 1];
    if (start[1] == n)  // every key has this digit zero: nothing moves
      continue;
    for (std::size_t b = 0; b < kBuckets; ++b)
      start[b + 1] += start[b];
    for (const std::uint64_t key : keys)
      buffer[start[(key >> shift) & (kBuckets - 1)]++] = key;
    keys.swap (buffer);
  }
  const std::uint64_t index_mask = (std::uint64_t (1) << index_bits) - 1;
  resizeOnHugePages (sorted.order, n);
  for (std::size_t v = 0; v < n; ++v)
    sorted.order[v] = static_cast<VertexIndex> (keys[v] & index_mask);
  if (with_codes)
  {
    resizeOnHugePages (sorted.codes, n);
    for (std::size_t v = 0; v < n; ++v)
      sorted.codes[v] = keys[v] >> index_bits;
  }
  return sorted;
}

PointMatrix
reorderPoints (const PointMatrix &points, const std::vector<VertexIndex> &order)
{
  PointMatrix out (static_cast<Eigen::Index> (order.size ()), 3);
  adviseHugePages (out.data (), order.size () * 3 * sizeof (float));
  for (std::size_t v = 0; v < order.size (); ++v)
    out.row (v) = points.row (order[v]);
  return out;
}

} // namespace detail
} // namespace core
} // namespace pcl_graph_denoise

/*
 * pcl_graph_denoise: graph-signal-processing point cloud denoising for PCL.
 * SPDX-License-Identifier: BSD-3-Clause
 */
#include "spatial_order.h"

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

} // namespace

std::vector<VertexIndex>
mortonOrder (const PointMatrix &points)
{
  const auto n = static_cast<std::size_t> (points.rows ());
  std::vector<VertexIndex> order (n);
  if (n == 0)
    return order;

  const Eigen::Vector3f lo = points.colwise ().minCoeff ();
  const Eigen::Vector3f hi = points.colwise ().maxCoeff ();
  const double extent = std::max ({double (hi.x ()) - lo.x (), double (hi.y ()) - lo.y (),
                                   double (hi.z ()) - lo.z ()});
  const double cells = double ((1u << 21) - 1);
  const double scale = extent > 0.0 ? cells / extent : 0.0;

  std::vector<std::pair<std::uint64_t, VertexIndex>> keyed (n);
  for (std::size_t i = 0; i < n; ++i)
  {
    std::uint64_t code = 0;
    for (int d = 0; d < 3; ++d)
    {
      const double cell = std::min (cells, (double (points (i, d)) - lo (d)) * scale);
      code |= spreadBits (static_cast<std::uint64_t> (cell)) << d;
    }
    keyed[i] = {code, static_cast<VertexIndex> (i)};
  }
  std::sort (keyed.begin (), keyed.end ());
  for (std::size_t v = 0; v < n; ++v)
    order[v] = keyed[v].second;
  return order;
}

PointMatrix
reorderPoints (const PointMatrix &points, const std::vector<VertexIndex> &order)
{
  PointMatrix out (static_cast<Eigen::Index> (order.size ()), 3);
  for (std::size_t v = 0; v < order.size (); ++v)
    out.row (v) = points.row (order[v]);
  return out;
}

} // namespace detail
} // namespace core
} // namespace pcl_graph_denoise

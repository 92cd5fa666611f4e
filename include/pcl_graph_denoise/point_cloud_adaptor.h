/*
 * pcl_graph_denoise: graph-signal-processing point cloud denoising for PCL.
 * SPDX-License-Identifier: BSD-3-Clause
 */
#pragma once

/** \file point_cloud_adaptor.h
 *  \brief The thin layer between PCL clouds and the numerical core: gathers the
 *  finite points a filter is asked to process into a plain matrix, and names
 *  where each row came from.
 */

#include <pcl_graph_denoise/core/graph.h>

#include <pcl/console/print.h>
#include <pcl/point_cloud.h>
#include <pcl/types.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <string>
#include <vector>

namespace pcl_graph_denoise {

/** \brief The finite points named by an index list, ready for the core (and, after
 *  addSearchSurface, the cloud's other finite points as neighbours only). */
struct GatheredPoints
{
  /** Positions relative to `origin`: one row per finite named point, in index-list order,
   *  then the `surface_only` rows. Centring in double keeps float precision for
   *  geo-referenced coordinates. */
  core::PointMatrix xyz;
  /** cloud_index[r] is the index in the cloud of row r of xyz. */
  pcl::Indices cloud_index;
  /** Indices (from the list, in its order) of points with a non-finite coordinate. */
  pcl::Indices non_finite;
  /** Number of entries of the list that repeat an earlier entry (used once). */
  std::size_t repeated = 0;
  /** Subtracted from every position: the mean of the finite named points, or their
   *  per-axis median where a few far points pull the mean away from the rest
   *  (originOf). */
  Eigen::Vector3d origin = Eigen::Vector3d::Zero ();
  /** Rows of xyz after the named points (addSearchSurface): the other finite points of
   *  the cloud, searched as neighbours only. Rows [0, cloud_index.size ()) are the named
   *  points. */
  std::size_t surface_only = 0;
  /** Indices (from the list, in its order) of named points taken out for lying too far
   *  from the others (takeOutFarPoints); not in cloud_index. */
  pcl::Indices far;
};

/** \brief Checks an index list against a cloud; returns an empty string when every
 *  index is in range, else a description of the first bad one. */
template <typename PointT>
std::string
checkIndices (const pcl::PointCloud<PointT> &cloud, const pcl::Indices &indices)
{
  for (const auto index : indices)
    if (index < 0 || static_cast<std::size_t> (index) >= cloud.size ())
      return "index " + std::to_string (index) + " is out of range for a cloud of " +
             std::to_string (cloud.size ()) + " points";
  return {};
}

/** \brief Why a filter call has nothing to work on (no finite point gathered): an empty
 *  index list, indices that name only non-finite points, or a cloud without a finite
 *  point (`user_indices`: the caller set the index list, PCLBase's !fake_indices_). */
inline std::string
noFinitePointReason (std::size_t cloud_size, std::size_t num_indices, bool user_indices)
{
  if (user_indices && num_indices == 0)
    return "the index list (setIndices) is empty (" + std::to_string (cloud_size) + " points)";
  if (user_indices)
    return "the " + std::to_string (num_indices) + " indices (setIndices) name no finite point of the " +
           std::to_string (cloud_size);
  return "the input has no finite point (" + std::to_string (cloud_size) + " points)";
}

/** \brief True when x, y and z of a point are all finite. */
template <typename PointT>
inline bool
isFinitePosition (const PointT &p)
{
  return std::isfinite (p.x) && std::isfinite (p.y) && std::isfinite (p.z);
}

/** \brief The per-axis median of the points of `cloud` named by `rows` (not empty). */
template <typename PointT>
Eigen::Vector3d
perAxisMedian (const pcl::PointCloud<PointT> &cloud, const pcl::Indices &rows)
{
  std::vector<double> values (rows.size ());
  const auto middle = values.begin () + std::ptrdiff_t (values.size () / 2);
  Eigen::Vector3d median;
  for (int d = 0; d < 3; ++d)
  {
    for (std::size_t r = 0; r < rows.size (); ++r)
      values[r] = cloud[rows[r]].getVector3fMap ()[d];
    std::nth_element (values.begin (), middle, values.end ());
    median[d] = *middle;
  }
  return median;
}

/** \brief The origin of gathered points, from their mean `mean` (computed in their
 *  order): the mean, unless along an axis it lies farther from the median than ten times
 *  the median distance of the points from the median (a few far points pull it there,
 *  and the rest, centred on it in single precision, would lose their detail: a point 10^9
 *  units away from a cloud a few units across collapsed it to a few positions); then the
 *  per-axis median. */
template <typename PointT>
Eigen::Vector3d
originOf (const pcl::PointCloud<PointT> &cloud, const pcl::Indices &rows,
          const Eigen::Vector3d &mean)
{
  if (rows.empty ())
    return mean;
  const Eigen::Vector3d median = perAxisMedian (cloud, rows);
  std::vector<double> distance (rows.size ());
  const auto middle = distance.begin () + std::ptrdiff_t (distance.size () / 2);
  bool pulled = false;
  for (int d = 0; d < 3; ++d)
  {
    for (std::size_t r = 0; r < rows.size (); ++r)
      distance[r] = std::abs (cloud[rows[r]].getVector3fMap ()[d] - median[d]);
    std::nth_element (distance.begin (), middle, distance.end ());
    pulled = pulled || std::abs (mean[d] - median[d]) > 10.0 * *middle;
  }
  return pulled ? median : mean;
}

/** \brief Sets the origin of `gathered` from the points of `cloud` its cloud_index names
 *  (their mean, or median: originOf) and its xyz to them relative to it, one row each. */
template <typename PointT>
void
centreGathered (const pcl::PointCloud<PointT> &cloud, GatheredPoints &gathered)
{
  const auto rows = static_cast<Eigen::Index> (gathered.cloud_index.size ());
  Eigen::Vector3d sum = Eigen::Vector3d::Zero ();
  for (const auto index : gathered.cloud_index)
    sum += Eigen::Vector3d (cloud[index].x, cloud[index].y, cloud[index].z);
  gathered.origin = rows > 0 ? originOf (cloud, gathered.cloud_index, sum / double (rows))
                             : Eigen::Vector3d::Zero ();
  gathered.xyz.resize (rows, 3);
  for (Eigen::Index r = 0; r < rows; ++r)
  {
    const PointT &p = cloud[gathered.cloud_index[r]];
    gathered.xyz (r, 0) = static_cast<float> (double (p.x) - gathered.origin.x ());
    gathered.xyz (r, 1) = static_cast<float> (double (p.y) - gathered.origin.y ());
    gathered.xyz (r, 2) = static_cast<float> (double (p.z) - gathered.origin.z ());
  }
}

/** \brief Gathers the finite points of `cloud` named by `indices` (which must be in
 *  range, see checkIndices). A repeated index is used once, at its first place; when
 *  `class_name` is given, that is reported with a PCL_WARN in the class's name. */
template <typename PointT>
GatheredPoints
gatherFinitePoints (const pcl::PointCloud<PointT> &cloud, const pcl::Indices &indices,
                    const char *class_name = nullptr)
{
  GatheredPoints out;
  std::vector<std::uint8_t> seen (cloud.size (), 0);
  out.cloud_index.reserve (indices.size ());
  for (const auto index : indices)
  {
    if (seen[index])
    {
      ++out.repeated;
      continue;
    }
    seen[index] = 1;
    const PointT &p = cloud[index];
    if (!isFinitePosition (p))
    {
      out.non_finite.push_back (index);
      continue;
    }
    out.cloud_index.push_back (index);
  }
  centreGathered (cloud, out);
  if (class_name && out.repeated > 0)
    PCL_WARN ("[pcl_graph_denoise::%s::applyFilter] %zu repeated indices were used once.\n",
              class_name, out.repeated);
  return out;
}

/** \brief Takes out of `gathered` (from gatherFinitePoints on `cloud`) the named points
 *  that lie farther than half of core::kMaxPointExtent from the named points' per-axis
 *  median along an axis (garbage coordinates such as a "no return" marker at 1e20, which
 *  no neighbour search can take with the rest), when they are fewer than half of the named
 *  points (else the cloud is too wide as a whole, and the graph says so): they go to
 *  gathered.far, and the rest is centred again as if they had not been named. With
 *  `class_name`, a PCL_WARN in the class's name says how many and what `fate` they get. */
template <typename PointT>
void
takeOutFarPoints (const pcl::PointCloud<PointT> &cloud, GatheredPoints &gathered,
                  const char *class_name, const char *fate)
{
  const std::size_t named = gathered.cloud_index.size ();
  // Points within the extent as a whole have none so far (one pass over the gathered
  // rows; the medians only where it is exceeded).
  if (named == 0 || !((gathered.xyz.colwise ().maxCoeff () - gathered.xyz.colwise ().minCoeff ())
                          .template cast<double> ()
                          .maxCoeff () > core::kMaxPointExtent))
    return;
  const Eigen::Vector3d median = perAxisMedian (cloud, gathered.cloud_index);
  const double reach = 0.5 * core::kMaxPointExtent;
  pcl::Indices near, far;
  for (const auto index : gathered.cloud_index)
  {
    const PointT &p = cloud[index];
    const bool beyond = ((Eigen::Vector3d (p.x, p.y, p.z) - median).cwiseAbs ().array () > reach).any ();
    (beyond ? far : near).push_back (index);
  }
  const std::size_t count = far.size ();
  if (count == 0 || 2 * count >= named)
    return;
  gathered.cloud_index.swap (near);
  gathered.far.swap (far);
  centreGathered (cloud, gathered);
  if (class_name)
    PCL_WARN ("[pcl_graph_denoise::%s::applyFilter] %zu of the %zu points lie more than %g "
              "units from the others' median along an axis, too far for any neighbour search "
              "with them: %s.\n",
              class_name, count, named, reach, fate);
}

/** \brief Appends to `gathered` (from gatherFinitePoints on `cloud`) the finite points of
 *  the cloud its index list does not name, in cloud order and relative to the same
 *  origin, as rows searched as neighbours only: PCL's filters search the whole input
 *  cloud for the points their indices name. Nothing is appended when no point is named
 *  (nothing to filter) or when every finite point is. A point that is not named and lies
 *  so far from the named ones that together they would span more than
 *  core::kMaxPointExtent along an axis (garbage coordinates such as 1e20, which the graph
 *  could not take) is not searched: the named points are filtered as if it were not
 *  there, and with `class_name` a PCL_WARN in the class's name says how many were left. */
template <typename PointT>
void
addSearchSurface (const pcl::PointCloud<PointT> &cloud, GatheredPoints &gathered,
                  const char *class_name = nullptr)
{
  const std::size_t named = gathered.cloud_index.size ();
  if (named == 0 || named + gathered.non_finite.size () + gathered.far.size () == cloud.size ())
    return;
  std::vector<std::uint8_t> is_named (cloud.size (), 0);
  for (const auto index : gathered.cloud_index)
    is_named[index] = 1;
  for (const auto index : gathered.far)
    is_named[index] = 1;
  // The box the others may reach: the named points' box widened on each side by half of
  // what the extent allows beyond it (relative to the origin, in double).
  Eigen::Vector3d low = Eigen::Vector3d::Constant (std::numeric_limits<double>::infinity ());
  Eigen::Vector3d high = -low;
  for (std::size_t r = 0; r < named; ++r)
  {
    const Eigen::Vector3d q = gathered.xyz.row (static_cast<Eigen::Index> (r)).template cast<double> ();
    low = low.cwiseMin (q);
    high = high.cwiseMax (q);
  }
  const double margin = std::max (0.0, 0.5 * (core::kMaxPointExtent - (high - low).maxCoeff ()));
  low.array () -= margin;
  high.array () += margin;
  pcl::Indices others;
  std::size_t too_far = 0;
  for (std::size_t i = 0; i < cloud.size (); ++i)
    if (!is_named[i] && isFinitePosition (cloud[i]))
    {
      const PointT &p = cloud[i];
      const Eigen::Vector3d q = Eigen::Vector3d (p.x, p.y, p.z) - gathered.origin;
      if ((q.array () < low.array ()).any () || (q.array () > high.array ()).any ())
        ++too_far;
      else
        others.push_back (static_cast<pcl::index_t> (i));
    }
  if (class_name && too_far > 0)
    PCL_WARN ("[pcl_graph_denoise::%s::applyFilter] %zu points not named by the indices lie "
              "so far from the named ones that together they would span more than %g units "
              "along an axis; they are not searched as neighbours.\n",
              class_name, too_far, core::kMaxPointExtent);
  if (others.empty ())
    return;
  const auto rows = static_cast<Eigen::Index> (named + others.size ());
  gathered.xyz.conservativeResize (rows, 3);
  for (std::size_t m = 0; m < others.size (); ++m)
  {
    const PointT &p = cloud[others[m]];
    const auto r = static_cast<Eigen::Index> (named + m);
    gathered.xyz (r, 0) = static_cast<float> (double (p.x) - gathered.origin.x ());
    gathered.xyz (r, 1) = static_cast<float> (double (p.y) - gathered.origin.y ());
    gathered.xyz (r, 2) = static_cast<float> (double (p.z) - gathered.origin.z ());
  }
  gathered.surface_only = others.size ();
}

/** \brief Moves the point of the cloud named by row r of `cloud_index` by the
 *  displacement of row r (position minus start, computed in double, so a point that did
 *  not move keeps its exact coordinates); only x, y and z change. Returns false, leaving the cloud partly
 *  written, when a moved coordinate is not finite (the positions overflowed). */
template <typename PointT>
bool
writeDisplacements (const pcl::Indices &cloud_index, const core::Signal3 &start,
                    const core::Signal3 &position, pcl::PointCloud<PointT> &cloud)
{
  for (std::size_t r = 0; r < cloud_index.size (); ++r)
  {
    PointT &p = cloud[cloud_index[r]];
    const auto row = static_cast<Eigen::Index> (r);
    const float x = static_cast<float> (double (p.x) + (position (row, 0) - start (row, 0)));
    const float y = static_cast<float> (double (p.y) + (position (row, 1) - start (row, 1)));
    const float z = static_cast<float> (double (p.z) + (position (row, 2) - start (row, 2)));
    if (!(std::isfinite (x) && std::isfinite (y) && std::isfinite (z)))
      return false;
    p.x = x;
    p.y = y;
    p.z = z;
  }
  return true;
}

} // namespace pcl_graph_denoise

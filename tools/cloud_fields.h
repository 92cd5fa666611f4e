/*
 * pcl_graph_denoise: graph-signal-processing point cloud denoising for PCL.
 * SPDX-License-Identifier: BSD-3-Clause
 */
#pragma once

#include <pcl/PCLPointCloud2.h>
#include <pcl/point_cloud.h>
#include <pcl/point_types.h>

#include <string>
#include <vector>

namespace pcl_graph_denoise {
namespace tools {

/** \brief The x, y and z fields of a pcl::PCLPointCloud2 (FLOAT32 or FLOAT64, one value
 *  each), the only bytes of it that the tool rewrites. */
class XyzFields
{
public:
  /** \brief Finds x, y and z in a cloud.
   *  \throws Error (naming `source`) if one is missing or is not a single float or double. */
  XyzFields (const pcl::PCLPointCloud2 &cloud, const std::string &source);

  /** \brief The positions as floats, less the origin (setCommonOrigin), with the cloud's
   *  width, height and density. */
  pcl::PointCloud<pcl::PointXYZ>::Ptr
  extract (const pcl::PCLPointCloud2 &cloud) const;

  /** \brief Moves the points of `cloud` where `after` differs from `before` (both from
   *  extract() and the filter): a float field receives the new value plus the origin, a
   *  double field its value plus the displacement, so that a point that did not move
   *  keeps its exact bytes. Returns the number of points moved. */
  std::size_t
  writeBack (pcl::PCLPointCloud2 &cloud, const pcl::PointCloud<pcl::PointXYZ> &before,
             const pcl::PointCloud<pcl::PointXYZ> &after) const;

  /** \brief Sets x, y and z of the point `index` to NaN. */
  void
  setNaN (pcl::PCLPointCloud2 &cloud, std::size_t index) const;

  /** \brief Takes the origin from `cloud` alone (setCommonOrigin with one cloud). */
  void
  centreOn (const pcl::PCLPointCloud2 &cloud);

private:
  friend void
  setCommonOrigin (std::vector<XyzFields> &fields, const std::vector<const pcl::PCLPointCloud2 *> &clouds);

  struct Field
  {
    std::uint32_t offset;
    std::uint8_t datatype;
  };
  /** Appends the double coordinates of every `stride`-th point with finite x, y, z to
   *  values[axis] (nothing on an axis stored as float). */
  void
  sampleCoordinates (const pcl::PCLPointCloud2 &cloud, std::size_t stride,
                     std::vector<double> values[3]) const;

  Field field_[3];
  /** What extract() subtracts from the coordinates (in double, before they become
   *  floats) and writeBack() adds back. */
  double origin_[3] = {0.0, 0.0, 0.0};
};

/** \brief Gives every cloud's fields the same origin: the median of the finite points'
 *  double coordinates, per axis (of every s-th point, about a million in all; 0 on an
 *  axis stored as float in every cloud). Geo-referenced coordinates (UTM: millions of
 *  metres) stored as doubles keep their precision through the filters, which work in
 *  float: at 4,000,000 m a float steps by 0.25 m. A median, so that a stray point (an
 *  exported (0, 0, 0)) cannot pull the origin away from the cloud as the centre of the
 *  bounding box did. One origin for all, so that the frames of a sequence stay in one
 *  frame of reference. */
void
setCommonOrigin (std::vector<XyzFields> &fields, const std::vector<const pcl::PCLPointCloud2 *> &clouds);

/** \brief The number of points with finite x, y and z. */
std::size_t
countFinite (const pcl::PointCloud<pcl::PointXYZ> &cloud);

/** \brief Byte address of point `index` (row-major over width x height) in a cloud. */
std::uint8_t *
pointData (pcl::PCLPointCloud2 &cloud, std::size_t index);
const std::uint8_t *
pointData (const pcl::PCLPointCloud2 &cloud, std::size_t index);

/** \brief A cloud with the same fields and metadata as `cloud` holding its points
 *  `indices` in that order, unorganised (height 1). */
pcl::PCLPointCloud2
selectPoints (const pcl::PCLPointCloud2 &cloud, const pcl::Indices &indices);

/** \brief Appends the points of `more` (same fields) to `cloud`, unorganised. */
void
appendPoints (pcl::PCLPointCloud2 &cloud, const pcl::PCLPointCloud2 &more);

}  // namespace tools
}  // namespace pcl_graph_denoise

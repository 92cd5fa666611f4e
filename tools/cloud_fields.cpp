/*
 * pcl_graph_denoise: graph-signal-processing point cloud denoising for PCL.
 * SPDX-License-Identifier: BSD-3-Clause
 */
#include "cloud_fields.h"

#include "cloud_io.h"

#include <pcl/common/io.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <stdexcept>

namespace pcl_graph_denoise {
namespace tools {

namespace {

double
readCoordinate (const std::uint8_t *p, std::uint8_t datatype)
{
  if (datatype == pcl::PCLPointField::FLOAT32)
  {
    float v;
    std::memcpy (&v, p, sizeof (v));
    return v;
  }
  double v;
  std::memcpy (&v, p, sizeof (v));
  return v;
}

void
writeCoordinate (std::uint8_t *p, std::uint8_t datatype, double value)
{
  if (datatype == pcl::PCLPointField::FLOAT32)
  {
    const float v = static_cast<float> (value);
    std::memcpy (p, &v, sizeof (v));
  }
  else
    std::memcpy (p, &value, sizeof (value));
}

bool
sameBits (float a, float b)
{
  return std::memcmp (&a, &b, sizeof (float)) == 0;
}

}  // namespace

std::uint8_t *
pointData (pcl::PCLPointCloud2 &cloud, std::size_t index)
{
  const std::size_t row = index / cloud.width, column = index % cloud.width;
  return cloud.data.data () + row * cloud.row_step + column * cloud.point_step;
}

const std::uint8_t *
pointData (const pcl::PCLPointCloud2 &cloud, std::size_t index)
{
  const std::size_t row = index / cloud.width, column = index % cloud.width;
  return cloud.data.data () + row * cloud.row_step + column * cloud.point_step;
}

XyzFields::XyzFields (const pcl::PCLPointCloud2 &cloud, const std::string &source)
{
  const char *names[3] = {"x", "y", "z"};
  for (int d = 0; d < 3; ++d)
  {
    const pcl::PCLPointField *found = nullptr;
    for (const auto &field : cloud.fields)
      if (field.name == names[d])
      {
        found = &field;
        break;
      }
    if (!found)
      throw Error (source + ": no '" + names[d] + "' field (fields: " +
                   (cloud.fields.empty () ? std::string ("none") : pcl::getFieldsList (cloud)) +
                   "): the tool needs x, y and z");
    if (found->datatype != pcl::PCLPointField::FLOAT32 &&
        found->datatype != pcl::PCLPointField::FLOAT64)
      throw Error (source + ": field '" + names[d] +
                   "' is not a float or a double (only FLOAT32 and FLOAT64 coordinates are "
                   "supported)");
    if (found->count != 1)
      throw Error (source + ": field '" + names[d] + "' has " + std::to_string (found->count) +
                   " values per point, expected 1");
    field_[d] = {found->offset, found->datatype};
  }
}

pcl::PointCloud<pcl::PointXYZ>::Ptr
XyzFields::extract (const pcl::PCLPointCloud2 &cloud) const
{
  auto xyz = std::make_shared<pcl::PointCloud<pcl::PointXYZ>> (cloud.width, cloud.height);
  bool dense = true;
  for (std::size_t i = 0; i < xyz->size (); ++i)
  {
    const std::uint8_t *p = pointData (cloud, i);
    pcl::PointXYZ &q = (*xyz)[i];
    float *out[3] = {&q.x, &q.y, &q.z};
    for (int d = 0; d < 3; ++d)
      *out[d] = static_cast<float> (readCoordinate (p + field_[d].offset, field_[d].datatype) - origin_[d]);
    dense = dense && std::isfinite (q.x) && std::isfinite (q.y) && std::isfinite (q.z);
  }
  xyz->is_dense = dense;
  return xyz;
}

std::size_t
XyzFields::writeBack (pcl::PCLPointCloud2 &cloud, const pcl::PointCloud<pcl::PointXYZ> &before,
                      const pcl::PointCloud<pcl::PointXYZ> &after) const
{
  std::size_t moved = 0;
  for (std::size_t i = 0; i < before.size (); ++i)
  {
    const float old_value[3] = {before[i].x, before[i].y, before[i].z};
    const float new_value[3] = {after[i].x, after[i].y, after[i].z};
    if (sameBits (old_value[0], new_value[0]) && sameBits (old_value[1], new_value[1]) &&
        sameBits (old_value[2], new_value[2]))
      continue;
    ++moved;
    std::uint8_t *p = pointData (cloud, i);
    for (int d = 0; d < 3; ++d)
    {
      std::uint8_t *value = p + field_[d].offset;
      if (field_[d].datatype == pcl::PCLPointField::FLOAT32)
        writeCoordinate (value, field_[d].datatype, double (new_value[d]) + origin_[d]);
      else
        writeCoordinate (value, field_[d].datatype,
                         readCoordinate (value, field_[d].datatype) +
                             (double (new_value[d]) - double (old_value[d])));
    }
  }
  return moved;
}

void
XyzFields::sampleCoordinates (const pcl::PCLPointCloud2 &cloud, std::size_t stride,
                              std::vector<double> values[3]) const
{
  const std::size_t n = std::size_t (cloud.width) * cloud.height;
  for (std::size_t i = 0; i < n; i += stride)
  {
    const std::uint8_t *p = pointData (cloud, i);
    double v[3];
    for (int d = 0; d < 3; ++d)
      v[d] = readCoordinate (p + field_[d].offset, field_[d].datatype);
    if (!(std::isfinite (v[0]) && std::isfinite (v[1]) && std::isfinite (v[2])))
      continue;
    for (int d = 0; d < 3; ++d)
      if (field_[d].datatype == pcl::PCLPointField::FLOAT64)
        values[d].push_back (v[d]);
  }
}

namespace {

/** At most about this many points are sampled (every s-th) for the origin's medians. */
constexpr std::size_t kOriginSamples = 1000000;

/** The median of `values`, 0 when there are none (no double coordinate on that axis). */
double
median (std::vector<double> &values)
{
  if (values.empty ())
    return 0.0;
  const auto middle = values.begin () + std::ptrdiff_t (values.size () / 2);
  std::nth_element (values.begin (), middle, values.end ());
  return *middle;
}

}  // namespace

void
setCommonOrigin (std::vector<XyzFields> &fields, const std::vector<const pcl::PCLPointCloud2 *> &clouds)
{
  if (fields.size () != clouds.size ())
    throw std::invalid_argument ("setCommonOrigin: one cloud per set of fields");
  std::size_t total = 0;
  for (const pcl::PCLPointCloud2 *cloud : clouds)
    total += std::size_t (cloud->width) * cloud->height;
  const std::size_t stride = std::max<std::size_t> (1, total / kOriginSamples);
  std::vector<double> values[3];
  for (std::size_t c = 0; c < clouds.size (); ++c)
    fields[c].sampleCoordinates (*clouds[c], stride, values);
  double origin[3];
  for (int d = 0; d < 3; ++d)
    origin[d] = median (values[d]);
  for (XyzFields &f : fields)
    for (int d = 0; d < 3; ++d)
      f.origin_[d] = origin[d];
}

void
XyzFields::centreOn (const pcl::PCLPointCloud2 &cloud)
{
  std::vector<XyzFields> one = {*this};
  setCommonOrigin (one, {&cloud});
  for (int d = 0; d < 3; ++d)
    origin_[d] = one[0].origin_[d];
}

void
XyzFields::setNaN (pcl::PCLPointCloud2 &cloud, std::size_t index) const
{
  std::uint8_t *p = pointData (cloud, index);
  for (int d = 0; d < 3; ++d)
    writeCoordinate (p + field_[d].offset, field_[d].datatype,
                     std::numeric_limits<double>::quiet_NaN ());
}

pcl::PCLPointCloud2
selectPoints (const pcl::PCLPointCloud2 &cloud, const pcl::Indices &indices)
{
  pcl::PCLPointCloud2 out;
  out.header = cloud.header;
  out.fields = cloud.fields;
  out.is_bigendian = cloud.is_bigendian;
  out.point_step = cloud.point_step;
  out.width = static_cast<std::uint32_t> (indices.size ());
  out.height = 1;
  out.row_step = out.width * out.point_step;
  out.is_dense = cloud.is_dense;
  out.data.resize (std::size_t (out.row_step));
  std::uint8_t *dst = out.data.data ();
  for (const auto index : indices)
  {
    std::memcpy (dst, pointData (cloud, static_cast<std::size_t> (index)), cloud.point_step);
    dst += cloud.point_step;
  }
  return out;
}

void
appendPoints (pcl::PCLPointCloud2 &cloud, const pcl::PCLPointCloud2 &more)
{
  if (cloud.fields.empty ())
  {
    cloud = selectPoints (more, pcl::Indices ());
    cloud.is_dense = true;
  }
  const std::size_t n = std::size_t (more.width) * more.height;
  cloud.data.reserve (cloud.data.size () + n * more.point_step);
  for (std::size_t i = 0; i < n; ++i)
  {
    const std::uint8_t *p = pointData (more, i);
    cloud.data.insert (cloud.data.end (), p, p + more.point_step);
  }
  cloud.width += static_cast<std::uint32_t> (n);
  cloud.height = 1;
  cloud.row_step = cloud.width * cloud.point_step;
  cloud.is_dense = cloud.is_dense && more.is_dense;
}

std::size_t
countFinite (const pcl::PointCloud<pcl::PointXYZ> &cloud)
{
  std::size_t n = 0;
  for (const auto &p : cloud)
    n += std::isfinite (p.x) && std::isfinite (p.y) && std::isfinite (p.z);
  return n;
}

}  // namespace tools
}  // namespace pcl_graph_denoise

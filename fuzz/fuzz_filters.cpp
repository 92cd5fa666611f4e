/*
 * pcl_graph_denoise: graph-signal-processing point cloud denoising for PCL.
 * SPDX-License-Identifier: BSD-3-Clause
 *
 * libFuzzer target: arbitrary bytes decoded into a small cloud (at most 200 points,
 * coordinates that may be NaN, +-Inf, huge, tiny, around 1e7, or repeated), parameters
 * for the three filters (k, sigma, gamma, radius, threshold rule, iterations, threads,
 * options) and possibly an index list (out of range, negative, repeated). Runs
 * GraphDegreeOutlierRemoval, GraphTikhonovSmoothing and GraphTVSmoothing and aborts when
 * an invariant breaks: the input changed, a result of the wrong size, a kept point that
 * is not finite or not named by the indices, a point that should not move moved, a
 * non-finite coordinate out of a finite one.
 *
 * Input layout (fuzz/make_corpus.py writes seeds in it):
 *   byte 0  flags: 1 CHOLMOD, 2 no normal displacement, 4 plane surface, 8 no shrinkage
 *           correction, 16 anisotropic TV, 32 negative, 64 keep organised, 128 organised
 *   byte 1  k: 0 -> 0, 254 -> -1, 255 -> INT_MAX, else the value
 *   byte 2  sigma: kValues[b % 32]; bit 5: quadrics over two rings (no adaptive support),
 *           bit 6: the own quadric instead of the blended quadrics, bit 7: a quadric at
 *           every point (patch cover 0)
 *   byte 3  gamma (255: automatic), byte 4 radius: kValues[b % 32]; bit 5: smoothing on the
 *           Gaussian weights (no density normalisation)
 *   byte 5  threshold rule (b & 3: ratio, absolute, fraction, default) and its value
 *           kValues[b >> 3]
 *   byte 6  b & 15: maximum iterations (0 stays 0: invalid), (b >> 4) & 3: graph
 *           iterations (0 stays 0: invalid), bit 6: two threads, bit 7: tolerance 1e-12
 *   byte 7  index list length (0: none); that many bytes follow, each an index
 *           (255 -> -1, else the value, which may exceed the cloud)
 *   then    points, each a kind byte and its payload (see decodePoint)
 */
#include "fuzz_check.h"

#include <pcl_graph_denoise/graph_degree_outlier_removal.h>
#include <pcl_graph_denoise/graph_tikhonov_smoothing.h>
#include <pcl_graph_denoise/graph_tv_smoothing.h>

#include <pcl/common/point_tests.h>
#include <pcl/console/print.h>
#include <pcl/point_types.h>

#include <climits>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <exception>
#include <limits>
#include <vector>

namespace {

using namespace pcl_graph_denoise;
using Cloud = pcl::PointCloud<pcl::PointXYZ>;

constexpr std::size_t kMaxPoints = 200;

const double kValues[32] = {0.0,    1e-300, 1e-30, 1e-6,  1e-3,  0.01,  0.05,  0.1,
                            0.3,    0.5,    1.0,   2.0,   10.0,  1e3,   1e6,   1e18,
                            1e30,   1e300,  std::numeric_limits<double>::quiet_NaN (),
                            std::numeric_limits<double>::infinity (),
                            -std::numeric_limits<double>::infinity (),
                            -1.0,   -1e-3,  3.4028234663852886e38,  1.1754943508222875e-38,
                            4.9e-324, 1e7,  3.0,   0.2,   0.02,  5.0,   100.0};

/** Reads the input front to back; past its end, zeros. */
struct Reader
{
  const std::uint8_t *data;
  std::size_t size, at = 0;

  bool
  more () const { return at < size; }

  std::uint8_t
  byte () { return at < size ? data[at++] : 0; }

  float
  rawFloat ()
  {
    std::uint8_t b[4] = {byte (), byte (), byte (), byte ()};
    float v;
    std::memcpy (&v, b, 4);
    return v;
  }
};

/** One point: kind & 7 selects the payload. */
pcl::PointXYZ
decodePoint (Reader &in, const Cloud &cloud)
{
  const std::uint8_t kind = in.byte ();
  pcl::PointXYZ p;
  const auto small = [&] () { return static_cast<float> (static_cast<std::int8_t> (in.byte ())) / 16.0f; };
  switch (kind & 7)
  {
  case 0:  // a grid of 1/16
    p.x = small (), p.y = small (), p.z = small ();
    break;
  case 1:  // any float bits
    p.x = in.rawFloat (), p.y = in.rawFloat (), p.z = in.rawFloat ();
    break;
  case 2:  // the previous point again
    p = cloud.empty () ? pcl::PointXYZ (0.0f, 0.0f, 0.0f) : cloud.back ();
    break;
  case 3:  // values of the table (NaN, Inf, huge, tiny...)
    p.x = static_cast<float> (kValues[in.byte () % 32]);
    p.y = static_cast<float> (kValues[in.byte () % 32]);
    p.z = static_cast<float> (kValues[in.byte () % 32]);
    break;
  case 4:  // micrometres
    p.x = small () * 1e-6f, p.y = small () * 1e-6f, p.z = small () * 1e-6f;
    break;
  case 5:  // geo-referenced
    p.x = 4.5e6f + small () * 64.0f, p.y = 1e7f + small () * 64.0f, p.z = 100.0f + small ();
    break;
  case 6:  // a finer grid
  {
    std::int16_t v[3];
    for (auto &c : v)
      c = static_cast<std::int16_t> (in.byte () | (in.byte () << 8));
    p.x = v[0] / 256.0f, p.y = v[1] / 256.0f, p.z = v[2] / 256.0f;
    break;
  }
  default:  // a hole
    p.x = p.y = p.z = std::numeric_limits<float>::quiet_NaN ();
  }
  return p;
}

bool
same (const pcl::PointXYZ &a, const pcl::PointXYZ &b)
{
  return std::memcmp (a.data, b.data, 3 * sizeof (float)) == 0;
}

bool
sameCloud (const Cloud &a, const Cloud &b)
{
  if (a.size () != b.size () || a.width != b.width || a.height != b.height || a.is_dense != b.is_dense)
    return false;
  for (std::size_t i = 0; i < a.size (); ++i)
    if (!same (a[i], b[i]))
      return false;
  return true;
}

double
value (std::uint8_t b)
{
  return kValues[b % 32];
}

int
integer (std::uint8_t b)
{
  return b == 255 ? INT_MAX : b == 254 ? -1 : b;
}

void
checkOutliers (const Cloud::Ptr &cloud, const pcl::IndicesPtr &indices, std::uint8_t flags,
               std::uint8_t radius, std::uint8_t rule, int threads)
{
  GraphDegreeOutlierRemoval<pcl::PointXYZ> filter (true);
  filter.setRadiusSearch (value (radius));
  filter.setSigma (value (radius >> 3));
  switch (rule & 3)
  {
  case 0:
    filter.setAutomaticThresholdRatio (value (rule >> 3));
    break;
  case 1:
    filter.setDegreeThreshold (value (rule >> 3));
    break;
  case 2:
    filter.setOutlierFraction (value (rule >> 3));
    break;
  default:
    break;
  }
  filter.setNegative (flags & 32);
  filter.setNumberOfThreads (threads);
  filter.setInputCloud (cloud);
  if (indices)
    filter.setIndices (indices);
  const std::size_t n = cloud->size ();
  std::vector<std::uint8_t> named (n, indices ? 0 : 1);
  bool valid = true;
  if (indices)
    for (const auto i : *indices)
    {
      if (i < 0 || std::size_t (i) >= n)
        valid = false;
      else
        named[i] = 1;
    }

  pcl::Indices kept;
  filter.filter (kept);
  const pcl::Indices removed = *filter.getRemovedIndices ();
  std::vector<std::uint8_t> seen (n, 0);
  for (const auto i : kept)
  {
    FUZZ_CHECK (valid);
    FUZZ_CHECK (i >= 0 && std::size_t (i) < n);
    FUZZ_CHECK (named[i] && pcl::isXYZFinite ((*cloud)[i]));
    FUZZ_CHECK (!seen[i]);
    seen[i] = 1;
  }
  for (const auto i : removed)
  {
    FUZZ_CHECK (i >= 0 && std::size_t (i) < n && named[i]);
    FUZZ_CHECK (!seen[i]);
    seen[i] = 1;
  }

  Cloud out;
  filter.setKeepOrganized (flags & 64);
  filter.filter (out);
  if (flags & 64)
  {
    if (!out.empty ())
    {
      // A copy of the input where the removed points are NaN.
      FUZZ_CHECK (out.size () == n && out.width == cloud->width && out.height == cloud->height);
      for (const auto i : kept)
        FUZZ_CHECK (same (out[i], (*cloud)[i]));
      for (const auto i : removed)
        FUZZ_CHECK (!pcl::isXYZFinite (out[i]));
    }
  }
  // An error (nothing kept or removed although points were named) leaves no output.
  const bool named_any = indices ? !indices->empty () : n > 0;
  if (named_any && kept.empty () && removed.empty ())
    FUZZ_CHECK (out.empty ());
  if (!(flags & 64))
    FUZZ_CHECK (out.size () == kept.size ());
}

void
checkSmoothing (GraphSmoothing<pcl::PointXYZ> &filter, const Cloud::Ptr &cloud,
                const pcl::IndicesPtr &indices, const std::uint8_t *p, int threads)
{
  const std::uint8_t flags = p[0];
  filter.setKSearch (integer (p[1]));
  filter.setSigma (value (p[2]));
  if (p[3] == 255)
    filter.setAutomaticGamma ();
  else
    filter.setGamma (value (p[3]));
  filter.setMaximumIterations (p[6] & 15);
  filter.setGraphIterations ((p[6] >> 4) & 3);
  if (p[6] & 128)
    filter.setTolerance (1e-12);
  filter.setNormalDisplacement (!(flags & 2));
  filter.setLocalSurface (flags & 4    ? LocalSurface::PLANE
                          : p[2] & 64 ? LocalSurface::QUADRIC
                                      : LocalSurface::BLENDED_QUADRICS);
  filter.setAdaptiveSupport (!(p[2] & 32));
  if (p[2] & 128)
    filter.setPatchCover (0);
  filter.setShrinkageCorrection (!(flags & 8));
  filter.setDensityNormalization (!(p[4] & 32));
  filter.setNumberOfThreads (threads);
  filter.setInputCloud (cloud);
  if (indices)
    filter.setIndices (indices);
  const std::size_t n = cloud->size ();
  std::vector<std::uint8_t> named (n, indices ? 0 : 1);
  if (indices)
    for (const auto i : *indices)
      if (i >= 0 && std::size_t (i) < n)
        named[i] = 1;

  Cloud out;
  filter.filter (out);
  if (out.empty ())
    return;  // an error (or an empty input)
  FUZZ_CHECK (out.size () == n && out.width == cloud->width && out.height == cloud->height);
  for (std::size_t i = 0; i < n; ++i)
  {
    if (!pcl::isXYZFinite ((*cloud)[i]) || !named[i])
      FUZZ_CHECK (same (out[i], (*cloud)[i]));  // passed through untouched
    else
      FUZZ_CHECK (pcl::isXYZFinite (out[i]));
  }
}

} // namespace

extern "C" int
LLVMFuzzerInitialize (int *, char ***)
{
  pcl::console::setVerbosityLevel (pcl::console::L_ALWAYS);
  return 0;
}

extern "C" int
LLVMFuzzerTestOneInput (const std::uint8_t *data, std::size_t size)
{
  Reader in{data, size};
  std::uint8_t p[7];
  for (auto &b : p)
    b = in.byte ();
  const std::uint8_t flags = p[0];
  const int threads = (p[6] & 64) ? 2 : 1;

  pcl::IndicesPtr indices;
  if (const std::uint8_t count = in.byte ())
  {
    indices = std::make_shared<pcl::Indices> ();
    for (int i = 0; i < count; ++i)
    {
      const std::uint8_t b = in.byte ();
      indices->push_back (b == 255 ? -1 : b);
    }
  }
  auto cloud = std::make_shared<Cloud> ();
  while (in.more () && cloud->size () < kMaxPoints)
    cloud->push_back (decodePoint (in, *cloud));
  bool dense = true;
  for (const auto &q : *cloud)
    dense = dense && pcl::isXYZFinite (q);
  cloud->is_dense = dense;
  if ((flags & 128) && cloud->size () >= 4)
  {
    const std::uint32_t height = 2 + (p[1] & 1);  // organised as width x 2 or 3
    cloud->resize (cloud->size () - cloud->size () % height);
    cloud->width = static_cast<std::uint32_t> (cloud->size ()) / height;
    cloud->height = height;
  }
  const Cloud before = *cloud;

  try
  {
    checkOutliers (cloud, indices, flags, p[4], p[5], threads);
    FUZZ_CHECK (sameCloud (*cloud, before));
    GraphTikhonovSmoothing<pcl::PointXYZ> tikhonov;
    tikhonov.setSolver (flags & 1 ? core::TikhonovSolver::CHOLMOD
                                  : core::TikhonovSolver::CONJUGATE_GRADIENT);
    checkSmoothing (tikhonov, cloud, indices, p, threads);
    FUZZ_CHECK (sameCloud (*cloud, before));
    GraphTVSmoothing<pcl::PointXYZ> tv;
    tv.setNorm (flags & 16 ? core::TotalVariationNorm::ANISOTROPIC
                           : core::TotalVariationNorm::ISOTROPIC);
    checkSmoothing (tv, cloud, indices, p, threads);
    FUZZ_CHECK (sameCloud (*cloud, before));
  }
  catch (const std::exception &e)
  {
    std::fprintf (stderr, "fuzz_filters: a filter threw: %s\n", e.what ());
    std::abort ();
  }
  return 0;
}

/*
 * pcl_graph_denoise: graph-signal-processing point cloud denoising for PCL.
 * SPDX-License-Identifier: BSD-3-Clause
 */
#include <pcl_graph_denoise/core/memory.h>

#include <unistd.h>

#include <algorithm>
#include <cstdint>
#include <cstdio>
#include <limits>
#include <stdexcept>

namespace pcl_graph_denoise {
namespace core {

namespace {

/* Bytes per point, a + b k, fitted to the peaks bench/bench_memory's jobs measured
 * (noisy spheres of 200,000 and 1,000,000 points, k = 5, 10 and 20, two threads; the PCL
 * layer's output cloud and gathered points taken off) and raised by about 15%, so that
 * each estimate is an upper bound without refusing clouds that fit. Measured, per point:
 * the graph alone 174 / 261 / 435 (k = 5 / 10 / 20: the Morton-ordered copy, the k-d
 * tree, the directed lists and their transpose, then up to 2k entries of index and
 * weight), Tikhonov 325 / 372 / 520 and TV 377 / 518 / 798 for the whole filter on
 * PointXYZ (TV adds the single-precision duals of every edge), CHOLMOD 1139 / 2177 / 4088
 * at 1M points and less at 200k (its fill-in grows faster than N: a rough bound). The
 * smoothing peak is the larger of the graph's build and the graph with the solver's
 * state (signals of N x 3 doubles, the normals' and quadric fits' results). The blended
 * quadrics kept every vertex's patch (17 doubles) for a second pass: measured again at
 * 1M points and k = 10 with them, Tikhonov 461 and TV 536, and Tikhonov's a raised by 70
 * to keep the margin; the patch centres of setPatchCover add a flag per point (and four
 * bytes of counts while they are chosen), within that margin, and since 2026-12-06 only
 * the vertices that carry a patch keep one (40% of them at the default cover; four bytes
 * per point of slot numbers), so that these bounds hold with room to spare. */
struct PerPoint
{
  double a, b;
};
constexpr PerPoint kGraph = {100.0, 20.0};
constexpr PerPoint kTikhonov = {300.0, 15.0};
constexpr PerPoint kTotalVariation = {210.0, 32.0};
constexpr PerPoint kCholmod = {320.0, 240.0};
constexpr double kRadiusDegreesPerPoint = 120.0;

std::size_t
saturate (long double bytes)
{
  const long double most = static_cast<long double> (std::numeric_limits<std::size_t>::max ());
  return bytes >= most ? std::numeric_limits<std::size_t>::max ()
                       : static_cast<std::size_t> (bytes);
}

std::size_t
cappedNeighbours (std::size_t n, std::size_t k)
{
  return n == 0 ? 0 : std::min (k, n - 1);
}

} // namespace

std::size_t
physicalMemory ()
{
#if defined(_SC_PHYS_PAGES) && defined(_SC_PAGE_SIZE)
  const long pages = ::sysconf (_SC_PHYS_PAGES), page = ::sysconf (_SC_PAGE_SIZE);
  if (pages > 0 && page > 0)
    return saturate (static_cast<long double> (pages) * page);
#endif
  return 0;
}

std::size_t
knnGraphMemory (std::size_t n, std::size_t k)
{
  const long double kk = cappedNeighbours (n, k);
  return saturate (static_cast<long double> (n) * (kGraph.a + kGraph.b * kk));
}

std::size_t
smoothingMemory (std::size_t n, std::size_t k, SmoothingKind kind)
{
  const PerPoint cost = kind == SmoothingKind::TIKHONOV          ? kTikhonov
                        : kind == SmoothingKind::TOTAL_VARIATION ? kTotalVariation
                                                                 : kCholmod;
  const long double kk = cappedNeighbours (n, k);
  const std::size_t solve = saturate (static_cast<long double> (n) * (cost.a + cost.b * kk));
  return std::max (solve, knnGraphMemory (n, k));
}

std::size_t
radiusDegreesMemory (std::size_t n)
{
  return saturate (static_cast<long double> (n) * kRadiusDegreesPerPoint);
}

void
requireMemory (std::size_t needed, std::size_t limit, const std::string &what,
               const std::string &lever)
{
  const std::size_t machine = limit == 0 ? physicalMemory () : 0;
  const std::size_t allowed = limit == 0 ? machine : limit;
  if (allowed == 0 || needed <= allowed)
    return;
  const std::string way_out = lever.empty () ? std::string (" or") : ", lower " + lever + ", or";
  char text[400];
  std::snprintf (text, sizeof (text),
                 "%s would need about %.3g GB, more than the %.3g GB %s: filter fewer points "
                 "(e.g. pcl::VoxelGrid first)%s raise the limit (setMemoryLimit)",
                 what.c_str (), double (needed) / 1e9, double (allowed) / 1e9,
                 limit == 0 ? "of memory of this machine" : "allowed by the memory limit",
                 way_out.c_str ());
  throw std::invalid_argument (text);
}

} // namespace core
} // namespace pcl_graph_denoise

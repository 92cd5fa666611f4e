/*
 * pcl_graph_denoise: graph-signal-processing point cloud denoising for PCL.
 * SPDX-License-Identifier: BSD-3-Clause
 */
#pragma once

/* Wall-clock timing for the benchmarks and the demo. */

#include <algorithm>
#include <chrono>
#include <vector>

namespace pcl_graph_denoise {

/** Seconds that f() took. */
template <typename F>
double
seconds (F &&f)
{
  const auto start = std::chrono::steady_clock::now ();
  f ();
  return std::chrono::duration<double> (std::chrono::steady_clock::now () - start).count ();
}

/** Median of the seconds that `repeats` calls of f() took (at least one call), each
 *  after an untimed call of prepare() (e.g. releasing the previous call's result, whose
 *  freeing is not part of what is timed): steadier than one call against a machine's
 *  passing load, and the same for both sides of a comparison. */
template <typename Prepare, typename F>
double
medianSeconds (int repeats, Prepare &&prepare, F &&f)
{
  std::vector<double> times;
  for (int r = 0; r < std::max (repeats, 1); ++r)
  {
    prepare ();
    times.push_back (seconds (f));
  }
  std::nth_element (times.begin (), times.begin () + times.size () / 2, times.end ());
  return times[times.size () / 2];
}

/** Median of the seconds that `repeats` calls of f() took (at least one call). */
template <typename F>
double
medianSeconds (int repeats, F &&f)
{
  return medianSeconds (repeats, [] {}, f);
}

} // namespace pcl_graph_denoise

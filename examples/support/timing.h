/*
 * pcl_graph_denoise: graph-signal-processing point cloud denoising for PCL.
 * SPDX-License-Identifier: BSD-3-Clause
 */
#pragma once

/* Wall-clock timing for the benchmarks and the demo. */

#include <chrono>

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

} // namespace pcl_graph_denoise

/*
 * pcl_graph_denoise: graph-signal-processing point cloud denoising for PCL.
 * SPDX-License-Identifier: BSD-3-Clause
 */
#pragma once

/* Peak memory of a piece of work, measured from outside the allocator (Linux): the
 * benchmark and the tests share it. */

#include <cstddef>
#include <functional>

namespace pcl_graph_denoise {
namespace synthetic {

struct PeakMemory
{
  double bytes = -1.0;       ///< peak resident size above the one at the start; < 0: failed
  double seconds = -1.0;     ///< wall time of the work
  std::size_t returned = 0;  ///< what the work returned (e.g. an estimate to compare)
};

/** Runs `work` in a child process (fork) that first resets its high-water mark
 *  (/proc/self/clear_refs) and returns its peak resident size (VmHWM) less the resident
 *  size at the start: what the work allocated and touched, not what the parent held
 *  before. Linux only; bytes < 0 when the measure is not available. */
PeakMemory
measurePeakMemory (const std::function<std::size_t ()> &work);

} // namespace synthetic
} // namespace pcl_graph_denoise

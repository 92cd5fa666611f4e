/*
 * pcl_graph_denoise: graph-signal-processing point cloud denoising for PCL.
 * SPDX-License-Identifier: BSD-3-Clause
 */
#include "wide_kernels.h"

#include <atomic>

namespace pcl_graph_denoise {
namespace core {
namespace detail {

namespace {

bool
processorHasAvx2 ()
{
#if PCL_GRAPH_DENOISE_WIDE_KERNELS
  // Initialised here too: a caller's static constructor may run before the runtime's.
  __builtin_cpu_init ();
  return __builtin_cpu_supports ("avx2");
#else
  return false;
#endif
}

std::atomic<bool> &
wideFlag ()
{
  static std::atomic<bool> flag (processorHasAvx2 ());
  return flag;
}

} // namespace

bool
wideKernelsEnabled ()
{
  return wideFlag ().load (std::memory_order_relaxed);
}

bool
setWideKernels (bool enabled)
{
  const bool on = enabled && processorHasAvx2 ();
  wideFlag ().store (on, std::memory_order_relaxed);
  return on;
}

} // namespace detail
} // namespace core
} // namespace pcl_graph_denoise

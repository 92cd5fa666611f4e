/*
 * pcl_graph_denoise: graph-signal-processing point cloud denoising for PCL.
 * SPDX-License-Identifier: BSD-3-Clause
 */
#pragma once

/* Private helper of the core: hot loops compiled twice, for the x86-64 baseline (SSE2)
 * and for AVX2, and run in the AVX2 build where the processor has it. The library is
 * built for the baseline so that it runs anywhere; a kernel is a lambda marked
 * PCL_GRAPH_DENOISE_KERNEL (always inlined, so that its body is compiled for the
 * instruction set of the function it is inlined into) run through wide(). Every
 * operation is the same IEEE operation in both builds (the files that use this are
 * compiled without floating-point contraction, and AVX2 alone has no fused
 * multiply-add), so the results are bit for bit the same: only more lanes per
 * instruction. */

#include <cstddef>

#if defined(__x86_64__) && (defined(__GNUC__) || defined(__clang__))
#define PCL_GRAPH_DENOISE_WIDE_KERNELS 1
#define PCL_GRAPH_DENOISE_KERNEL __attribute__ ((always_inline))
#else
#define PCL_GRAPH_DENOISE_WIDE_KERNELS 0
#define PCL_GRAPH_DENOISE_KERNEL
#endif

namespace pcl_graph_denoise {
namespace core {
namespace detail {

/** Whether wide() runs the AVX2 build: by default where the processor has AVX2. */
bool
wideKernelsEnabled ();

/** Turns the AVX2 build off (or back on, where the processor has it); for the tests
 *  that compare the two builds. Returns whether it is now on. */
bool
setWideKernels (bool enabled);

#if PCL_GRAPH_DENOISE_WIDE_KERNELS
template <typename Kernel>
__attribute__ ((target ("avx2"))) auto
runAvx2 (const Kernel &kernel, std::size_t begin, std::size_t end)
{
  return kernel (begin, end);
}
#endif

/** kernel(begin, end), in its AVX2 build where that is enabled. */
template <typename Kernel>
auto
wide (const Kernel &kernel, std::size_t begin, std::size_t end)
{
#if PCL_GRAPH_DENOISE_WIDE_KERNELS
  if (wideKernelsEnabled ())
    return runAvx2 (kernel, begin, end);
#endif
  return kernel (begin, end);
}

} // namespace detail
} // namespace core
} // namespace pcl_graph_denoise

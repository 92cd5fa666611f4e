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
#include <cstdint>
#include <cstring>

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

/** exp(x) for x <= 0 (0 below -708, where exp(x) leaves the normal doubles) as plain
 *  arithmetic that the compiler vectorises in a kernel's loop: Cody and Waite's
 *  reduction x = k ln 2 + r, |r| <= ln(2) / 2, the Taylor polynomial of degree 13 of
 *  exp(r) (truncation below 2e-16 relative) and 2^k put into the exponent's bits. Within
 *  2.1e-16 of std::exp relative on [-40, 0] (as close as Eigen's vectorised exp), the same
 *  bits in both builds, and about 3 times the speed of Eigen's in the AVX2 one. */
PCL_GRAPH_DENOISE_KERNEL inline double
expOfNonPositive (double x)
{
  const bool underflow = !(x >= -708.0);  // also NaN: no weight
  x = underflow ? -708.0 : x;
  // k = round(x / ln 2), as the low bits of t (the shifter 1.5 2^52 keeps them integral).
  constexpr double kShifter = 0x1.8p52;
  const double t = x * 1.4426950408889634074 + kShifter;
  const double k = t - kShifter;
  const double r = (x - k * 6.93147180369123816490e-01) - k * 1.90821492927058770002e-10;
  double p = 1.0 / 6227020800.0;
  p = p * r + 1.0 / 479001600.0;
  p = p * r + 1.0 / 39916800.0;
  p = p * r + 1.0 / 3628800.0;
  p = p * r + 1.0 / 362880.0;
  p = p * r + 1.0 / 40320.0;
  p = p * r + 1.0 / 5040.0;
  p = p * r + 1.0 / 720.0;
  p = p * r + 1.0 / 120.0;
  p = p * r + 1.0 / 24.0;
  p = p * r + 1.0 / 6.0;
  p = p * r + 0.5;
  p = p * r + 1.0;
  p = p * r + 1.0;
  std::uint64_t t_bits, p_bits;
  std::memcpy (&t_bits, &t, sizeof (t));
  std::memcpy (&p_bits, &p, sizeof (p));
  p_bits += t_bits << 52;  // k (two's complement in t's low bits) onto p's exponent
  double out;
  std::memcpy (&out, &p_bits, sizeof (out));
  return underflow ? 0.0 : out;
}

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

/*
 * pcl_graph_denoise: graph-signal-processing point cloud denoising for PCL.
 * SPDX-License-Identifier: BSD-3-Clause
 */
#pragma once

/* Private to the core: large buffers on transparent huge pages.
 *
 * The first write to fresh memory costs a page fault per 4 KiB page, and on virtual
 * machines that fault is slow: 2.7 ms per MiB was measured on the project's machines
 * (Firecracker VMs), more than the k-NN search of the same points takes. Where the
 * kernel offers transparent huge pages on request (Debian's default, "madvise"), the
 * buffers asked for here are faulted in 2 MiB at a time instead (about 5x faster
 * there); elsewhere the request is ignored. */

#include <Eigen/Core>

#include <cstddef>
#include <cstdint>
#include <vector>

#if defined(__linux__)
#include <sys/mman.h>
#endif

namespace pcl_graph_denoise {
namespace core {
namespace detail {

/** Asks for huge pages for the whole 2 MiB pages within [data, data + bytes), before
 *  anything is written there (none in buffers under 2 MiB). */
inline void
adviseHugePages (void *data, std::size_t bytes)
{
#if defined(__linux__) && defined(MADV_HUGEPAGE)
  constexpr std::uintptr_t kHuge = std::uintptr_t (1) << 21;
  if (bytes < kHuge)
    return;
  const auto first = (reinterpret_cast<std::uintptr_t> (data) + kHuge - 1) & ~(kHuge - 1);
  const auto last = (reinterpret_cast<std::uintptr_t> (data) + bytes) & ~(kHuge - 1);
  if (last > first)
    madvise (reinterpret_cast<void *> (first), last - first, MADV_HUGEPAGE);  // a hint
#else
  (void) data;
  (void) bytes;
#endif
}

/** v.reserve (n), with fresh storage on huge pages when it needs more than it has. */
template <typename T>
void
reserveOnHugePages (std::vector<T> &v, std::size_t n)
{
  if (n > v.capacity ())
  {
    std::vector<T> fresh;
    fresh.reserve (n);
    adviseHugePages (fresh.data (), n * sizeof (T));
    fresh.assign (v.begin (), v.end ());
    v.swap (fresh);
  }
}

/** v.resize (n) (value-initialised), with fresh storage on huge pages when it needs
 *  more than it has. */
template <typename T>
void
resizeOnHugePages (std::vector<T> &v, std::size_t n)
{
  reserveOnHugePages (v, n);
  v.resize (n);
}

/** An uninitialised matrix of `rows` rows (and its type's fixed number of columns), its
 *  storage on huge pages: for the signals of N x 3 values that the solvers and the
 *  quadric step allocate afresh (at a million points each is 12 or 24 MB). */
template <typename Matrix>
Matrix
matrixOnHugePages (Eigen::Index rows)
{
  Matrix m (rows, Matrix::ColsAtCompileTime);
  adviseHugePages (m.data (), static_cast<std::size_t> (m.size ()) * sizeof (typename Matrix::Scalar));
  return m;
}

} // namespace detail
} // namespace core
} // namespace pcl_graph_denoise

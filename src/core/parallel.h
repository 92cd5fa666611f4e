/*
 * pcl_graph_denoise: graph-signal-processing point cloud denoising for PCL.
 * SPDX-License-Identifier: BSD-3-Clause
 */
#pragma once

/* Private helper of the core: a parallel loop over [0, n) on std::threads.
 * Work is handed out in fixed blocks; callers write only to per-item outputs, so
 * results never depend on the number of threads or on scheduling. */

#include <algorithm>
#include <atomic>
#include <cstddef>
#include <exception>
#include <mutex>
#include <thread>
#include <vector>

namespace pcl_graph_denoise {
namespace core {
namespace detail {

/** Number of worker threads for a request (0 = hardware concurrency). */
inline int
resolveThreads (int requested)
{
  if (requested > 0)
    return requested;
  const unsigned hw = std::thread::hardware_concurrency ();
  return hw == 0 ? 1 : static_cast<int> (hw);
}

/** Calls body(begin, end) on disjoint blocks covering [0, n). */
template <typename Body>
void
parallelFor (std::size_t n, int num_threads, Body &&body, std::size_t block = 4096)
{
  if (n == 0)
    return;
  block = std::max<std::size_t> (block, 1);
  const std::size_t num_blocks = (n + block - 1) / block;
  const int threads =
      static_cast<int> (std::min<std::size_t> (num_blocks, resolveThreads (num_threads)));
  if (threads <= 1)
  {
    body (std::size_t (0), n);
    return;
  }
  std::atomic<std::size_t> next_block (0);
  std::exception_ptr error;
  std::mutex error_mutex;
  auto worker = [&] () {
    try
    {
      for (std::size_t b = next_block++; b < num_blocks; b = next_block++)
        body (b * block, std::min (n, (b + 1) * block));
    }
    catch (...)
    {
      std::lock_guard<std::mutex> lock (error_mutex);
      if (!error)
        error = std::current_exception ();
      next_block = num_blocks;
    }
  };
  std::vector<std::thread> pool;
  pool.reserve (threads - 1);
  for (int t = 1; t < threads; ++t)
    pool.emplace_back (worker);
  worker ();
  for (auto &thread : pool)
    thread.join ();
  if (error)
    std::rethrow_exception (error);
}

/** Deterministic parallel reduction: body(begin, end) returns a partial value for a
 *  block; the partials of fixed blocks are added in block order, so the sum does not
 *  depend on the number of threads. T needs T{} as zero and operator+=. */
template <typename T, typename Body>
T
parallelSum (std::size_t n, int num_threads, Body &&body, std::size_t block = 4096)
{
  const std::size_t num_blocks = (n + block - 1) / block;
  std::vector<T> partial (num_blocks, T{});
  parallelFor (
      num_blocks, num_threads,
      [&] (std::size_t first, std::size_t last) {
        for (std::size_t b = first; b < last; ++b)
          partial[b] = body (b * block, std::min (n, (b + 1) * block));
      },
      1);
  T sum{};
  for (const T &p : partial)
    sum += p;
  return sum;
}

} // namespace detail
} // namespace core
} // namespace pcl_graph_denoise

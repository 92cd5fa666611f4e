/*
 * pcl_graph_denoise: graph-signal-processing point cloud denoising for PCL.
 * SPDX-License-Identifier: BSD-3-Clause
 */
#pragma once

/* Private to the core: sorting and selecting among a few distinct keys by rank, without
 * branches. The graph's rows and the k-NN search's candidates are short lists; there a
 * key's rank (how many keys are smaller) costs m comparisons that never mispredict, where
 * std::sort and std::nth_element branch on every comparison. On the k-NN graph of a noisy
 * 100,000-point sphere (k = 10) the pass that sorts and weighs the rows took 14-17 ms
 * instead of 17-23 ms with std::sort. */

#include <algorithm>
#include <cstddef>

namespace pcl_graph_denoise {
namespace core {
namespace detail {

/** The longest list ranked rather than sorted or selected by the standard algorithms
 *  (the rank costs m^2 comparisons). */
constexpr std::size_t kRankedList = 32;

/** Puts the `keep` smallest of the m distinct keys at `keys` first, ascending; what the
 *  other m - keep places hold afterwards is unspecified. Needs keep <= m. */
template <typename Key>
void
smallestFirst (Key *keys, std::size_t m, std::size_t keep)
{
  if (keep == 0)
    return;
  if (m > kRankedList)
  {
    if (keep < m)
      std::nth_element (keys, keys + (keep - 1), keys + m);
    std::sort (keys, keys + keep);
    return;
  }
  Key copy[kRankedList];
  std::copy (keys, keys + m, copy);
  for (std::size_t a = 0; a < m; ++a)
  {
    std::size_t rank = 0;
    for (std::size_t b = 0; b < m; ++b)
      rank += copy[b] < copy[a];
    if (rank < keep)
      keys[rank] = copy[a];
  }
}

} // namespace detail
} // namespace core
} // namespace pcl_graph_denoise

/*
 * pcl_graph_denoise: graph-signal-processing point cloud denoising for PCL.
 * SPDX-License-Identifier: BSD-3-Clause
 */
#pragma once

/* The benchmarks' command line: a list of point counts. */

#include <cerrno>
#include <cstddef>
#include <cstdio>
#include <cstdlib>
#include <vector>

namespace pcl_graph_denoise {

/** The point counts given as arguments (`defaults` when there is none). Each must be a
 *  whole number from 2 to 2^32 - 1; anything else prints a usage line and gives an empty
 *  list, on which the caller exits with status 2. */
inline std::vector<std::size_t>
pointCounts (int argc, char **argv, const std::vector<std::size_t> &defaults)
{
  std::vector<std::size_t> counts;
  for (int a = 1; a < argc; ++a)
  {
    char *end = nullptr;
    errno = 0;
    const unsigned long long n = std::strtoull (argv[a], &end, 10);
    if (end == argv[a] || *end != '\0' || errno != 0 || argv[a][0] == '-' || n < 2 ||
        n > 0xFFFFFFFFull)
    {
      std::fprintf (stderr, "usage: %s [points ...]   (whole numbers from 2; bad: '%s')\n",
                    argv[0], argv[a]);
      return {};
    }
    counts.push_back (static_cast<std::size_t> (n));
  }
  return argc > 1 ? counts : defaults;
}

} // namespace pcl_graph_denoise

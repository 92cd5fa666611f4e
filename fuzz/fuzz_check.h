/*
 * pcl_graph_denoise: graph-signal-processing point cloud denoising for PCL.
 * SPDX-License-Identifier: BSD-3-Clause
 *
 * What the fuzz targets share: FUZZ_CHECK aborts with the failed condition and its place,
 * which libFuzzer reports as a crash and keeps the input for.
 */
#pragma once

#include <cstdio>
#include <cstdlib>

#define FUZZ_CHECK(condition)                                                                  \
  do                                                                                           \
  {                                                                                            \
    if (!(condition))                                                                          \
    {                                                                                          \
      std::fprintf (stderr, "invariant failed: %s (%s:%d)\n", #condition, __FILE__, __LINE__); \
      std::abort ();                                                                           \
    }                                                                                          \
  } while (0)

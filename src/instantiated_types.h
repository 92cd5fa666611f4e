/*
 * pcl_graph_denoise: graph-signal-processing point cloud denoising for PCL.
 * SPDX-License-Identifier: BSD-3-Clause
 */
#pragma once

/* The point types the library is pre-compiled for: PCL_XYZ_POINT_TYPES, or the list
 * given to CMake as PCL_GRAPH_DENOISE_POINT_TYPES (a PCL type sequence, set by the build
 * as a compile definition). */

#include <pcl/impl/instantiate.hpp>
#include <pcl/point_types.h>

#ifdef PCL_GRAPH_DENOISE_POINT_TYPES
#define PCL_GRAPH_DENOISE_INSTANTIATED_TYPES PCL_GRAPH_DENOISE_POINT_TYPES
#else
#define PCL_GRAPH_DENOISE_INSTANTIATED_TYPES PCL_XYZ_POINT_TYPES
#endif

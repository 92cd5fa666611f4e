/*
 * pcl_graph_denoise: graph-signal-processing point cloud denoising for PCL.
 * SPDX-License-Identifier: BSD-3-Clause
 */
#include <pcl_graph_denoise/graph_smoothing.h>

#ifndef PCL_NO_PRECOMPILE
#include <pcl_graph_denoise/impl/graph_smoothing.hpp>

#include "instantiated_types.h"

PCL_INSTANTIATE (GraphSmoothing, PCL_GRAPH_DENOISE_INSTANTIATED_TYPES)
#endif

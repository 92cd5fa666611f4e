/*
 * pcl_graph_denoise: graph-signal-processing point cloud denoising for PCL.
 * SPDX-License-Identifier: BSD-3-Clause
 */
#include <pcl_graph_denoise/graph_degree_outlier_removal.h>

#ifndef PCL_NO_PRECOMPILE
#include <pcl_graph_denoise/impl/graph_degree_outlier_removal.hpp>

#include "instantiated_types.h"

PCL_INSTANTIATE (GraphDegreeOutlierRemoval, PCL_GRAPH_DENOISE_INSTANTIATED_TYPES)
#endif

/*
 * pcl_graph_denoise: graph-signal-processing point cloud denoising for PCL.
 * SPDX-License-Identifier: BSD-3-Clause
 */
#pragma once

/* Private to the core: the exact Tikhonov solve through SuiteSparse's CHOLMOD, kept
 * out of every public header. */

#include <pcl_graph_denoise/core/graph.h>

namespace pcl_graph_denoise {
namespace core {
namespace detail {

/** x = (I + 2 gamma L)^-1 f by a sparse Cholesky factorisation.
 *  \throws std::runtime_error when CHOLMOD fails (e.g. out of memory). */
Signal3
solveTikhonovCholmod (const PointGraph &graph, const Signal3 &f, double gamma);

} // namespace detail
} // namespace core
} // namespace pcl_graph_denoise

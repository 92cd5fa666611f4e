/*
 * pcl_graph_denoise: graph-signal-processing point cloud denoising for PCL.
 * SPDX-License-Identifier: BSD-3-Clause
 */
#pragma once

/** \file normals.h
 *  \brief Surface normals on the graph, and displacements restricted to them: smoothing
 *  that moves points across the surface but not along it. */

#include <pcl_graph_denoise/core/graph.h>

namespace pcl_graph_denoise {
namespace core {

/** \brief Unit normal of every vertex: the direction of least variance of the points
 *  of the vertex and its two rings of graph neighbours (a local plane fit). A vertex
 *  with fewer than three points in its rings gets the zero vector. The sign is
 *  arbitrary (normals are not oriented). `points` are in the graph's vertex order;
 *  the result is independent of the number of threads. */
Signal3
estimateNormals (const PointGraph &graph, const Signal3 &points, int num_threads = 0);

/** \brief f + ((x - f) . n) n for every row: the displacement from f to x restricted
 *  to the normal n (a zero normal keeps the point at f).
 *  \throws std::invalid_argument when the sizes differ. */
Signal3
normalDisplacement (const Signal3 &f, const Signal3 &x, const Signal3 &normals);

} // namespace core
} // namespace pcl_graph_denoise

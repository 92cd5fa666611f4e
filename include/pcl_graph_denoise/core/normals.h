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

/** \brief Moves every point of f along a normal onto a local second-order surface
 *  fitted to the estimate x: for vertex i, the points of x over its two graph rings
 *  give a frame (origin x_i, normal = direction of least variance) and a quadric height
 *  field h(u, v) fitted by least squares, robustly: with `noise` > 0, each of four fits
 *  weights the points by exp(-r^2 / (2 noise^2)) of their residual r to the previous
 *  one (the first: to the plane through x_i), so that points of
 *  another sheet (the far side of a thin wall, the other face at a sharp edge) stop
 *  pulling the surface. The result is f_i moved along that normal to height h at its
 *  own (u, v): no tangential drift, and no flattening of curved surfaces (where the
 *  plane of normalDisplacement cuts chords). A vertex with fewer than 10 points in its
 *  rings falls back to the plane; with fewer than 3, it keeps x_i. f and x are in the
 *  graph's vertex order; the result is independent of the number of threads.
 *  \throws std::invalid_argument when the sizes differ. */
Signal3
quadricDisplacement (const PointGraph &graph, const Signal3 &f, const Signal3 &x, double noise,
                     int num_threads = 0);

} // namespace core
} // namespace pcl_graph_denoise

/*
 * pcl_graph_denoise: graph-signal-processing point cloud denoising for PCL.
 * SPDX-License-Identifier: BSD-3-Clause
 */
#pragma once

/** \file normals.h
 *  \brief Surface normals on the graph, and displacements restricted to them: smoothing
 *  that moves points across the surface but not along it, and the offset along the
 *  normal between two frames' surfaces (motion compensation of a sequence). */

#include <pcl_graph_denoise/core/graph.h>

#include <cstdint>
#include <vector>

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

/** \brief Which local surfaces a point moves onto in quadricDisplacement. */
enum class QuadricProjection
{
  OWN_PATCH,  ///< the quadric fitted around the point's own vertex
  BLENDED     ///< the weighted mean of the quadrics around it (default of the filters)
};

/** \brief Over which graph neighbourhood quadricDisplacement fits each vertex's quadric. */
enum class QuadricSupport
{
  TWO_RINGS,    ///< the vertex's two rings
  THREE_RINGS,  ///< its three rings everywhere (for comparison)
  /** Also over its three rings, and that wider fit is kept where its surface agrees
   *  with the two-ring fit's under the two-ring points: root-sum-square distance at most
   *  2 sqrt(6) noise levels (two standard errors per coefficient of a quadric). A larger
   *  support averages more noise where the surface is smooth at that scale; the test
   *  keeps the narrow fit where it bends or ends (an intersection of confidence
   *  intervals, as in Katkovnik's LPA-ICI). Without a noise level, TWO_RINGS. The
   *  filters' default (docs/evaluation.md, section 5). */
  ADAPTIVE
};

/** \brief Moves every point of f along a normal onto a local second-order surface
 *  fitted to the estimate x: for vertex i, the points of x over its two graph rings
 *  (or three: `support`) give a frame (origin x_i, normal = direction of least
 *  variance) and a quadric height field h(u, v) fitted by least squares, robustly:
 *  with `noise` > 0, each of up to four fits
 *  weights the points by exp(-r^2 / (2 noise^2)) of their residual r to the previous
 *  one (the first: to the plane through x_i; from the third on, only while the previous
 *  fit still moved the surface by more than noise / 10 at some point), so that points of
 *  another sheet (the far side of a thin wall, the other face at a sharp edge) stop
 *  pulling the surface. With QuadricProjection::OWN_PATCH the result is f_i moved along
 *  vertex i's normal to height h at its own (u, v): no tangential drift, and no
 *  flattening of curved surfaces (where the plane of normalDisplacement cuts chords).
 *  With QuadricProjection::BLENDED, f_i is moved likewise onto the patch of every vertex j of
 *  its two rings (i included), and the result is the mean of those positions weighted
 *  by exp(-d^2 / (2 (r_j / 2)^2) - e^2 / (2 noise^2)), d the tangential distance of x_i
 *  from x_j, r_j the RMS tangential spread of j's rings, e the distance of x_i from j's
 *  surface along its normal: overlapping fits average out their own noise (as patch
 *  estimates are aggregated in image denoising), and a patch of another sheet drops
 *  out. With a `patch_cover` c > 0 (BLENDED only), only the vertices of patchCentres (c)
 *  carry a patch, and a point blends those of its two rings; when none of them counts
 *  for it (or a centre has no surface of its own) it keeps x_i. A vertex with fewer
 *  than 10 points in its rings has the plane as its surface;
 *  with fewer than 3, none, and keeps x_i. Each move along a normal is limited, with a
 *  noise level, to |f_i - x_i| plus three noise levels. f and x are in the graph's
 *  vertex order; the result is independent of the number of threads.
 *  \throws std::invalid_argument when the sizes differ or patch_cover < 0. */
Signal3
quadricDisplacement (const PointGraph &graph, const Signal3 &f, const Signal3 &x, double noise,
                     int num_threads = 0,
                     QuadricProjection projection = QuadricProjection::OWN_PATCH,
                     QuadricSupport support = QuadricSupport::TWO_RINGS, int patch_cover = 0);

/** \brief The vertices that carry a quadric in quadricDisplacement's blend (1) and those
 *  that only borrow their neighbours' (0), for a cover c: in vertex order, a vertex
 *  carries one unless c of its graph neighbours already do, so that every vertex
 *  carries one or has at least c neighbours that do. c = 0: every vertex. Where the
 *  fits overlap this much, blending fewer of them loses little: on the calibration set
 *  of bench/calibrate_gamma (96 clouds), c = 3 fits about 40% of the vertices, for
 *  0.7% more error than a fit at every vertex (docs/evaluation.md, section 5).
 *  Independent of the number of threads (one pass in order).
 *  \throws std::invalid_argument when c < 0. */
std::vector<std::uint8_t>
patchCentres (const PointGraph &graph, int cover);

/** \brief Parameters of surfaceOffsets. */
struct SurfaceOffsetParams
{
  /** Points of each cloud around a point that give its local surface. Valid: >= 3. */
  int k = 30;
  /** Offsets smaller than this many standard errors of their own estimate are taken as
   *  noise: the offset is shrunk towards zero by that much (soft threshold), so that a
   *  surface that did not move is not moved by the noise of the estimate. Valid: >= 0,
   *  finite. */
  double significance = 2.0;
  /** Most rounds of the rigid alignment that comes first (a point-to-plane fit of the
   *  offsets, robust to the points that do not follow it, stopping when a round moves
   *  the points by less than a hundredth of the offsets' typical standard error); 0 =
   *  none, the offsets alone. Valid: >= 0. */
  int rigid_iterations = 5;
  /** Worker threads; 0 = all hardware threads. The result does not depend on it. */
  int num_threads = 0;
};

/** \brief For every point q of `moving`, the displacement that carries the surface
 *  `moving` samples around q onto the surface `reference` samples there (motion
 *  compensation between two frames of a sequence). The local offset: A and B are the
 *  points of `moving` and `reference` among the 2k nearest of q in each, over one disk
 *  around q measured across the surfaces' normal (as far as q's k nearest in `moving`
 *  reach, q included, or the 2k nearest in `reference` where those reach less far) and
 *  within one ball that both sets of 2k cover (around q for A, around q moved by the
 *  neighbourhoods' offset for B), so that frames of different densities sample the same
 *  part of a curved surface and both take in as much of the other face at a sharp edge;
 *  n the direction of least variance of A and
 *  B each about its own mean (the two surfaces are locally parallel); the offset is
 *  n . (mean B - mean A), with a standard error from the spread of A and B about their
 *  planes; 0 where either has fewer than 3 points in the disk or B's mean lies off to the
 *  side of A by more than A's extent (the reference does not cover that part). First the
 *  rigid motion that best explains these offsets (point-to-plane, robust,
 *  rigid_iterations rounds, each principal direction of the fit shrunk as the offsets
 *  are) is applied; then each point also moves along n by its remaining offset, shrunk where it is
 *  not significant (non-negative garrote: 0 below `significance` standard errors, offset -
 *  limit^2 / offset above) and averaged over q's k nearest (a surface moves smoothly; the noise of the
 *  estimates does not). Only the part of a motion that moves the surface is seen (a
 *  surface sliding along itself gives no offset, and needs none for smoothing). Zero for
 *  every point when either cloud has fewer than 3 points. The result is independent of
 *  the number of threads.
 *  \throws std::invalid_argument for invalid parameters or non-finite points. */
Signal3
surfaceOffsets (const PointMatrix &moving, const PointMatrix &reference,
                const SurfaceOffsetParams &params = {});

} // namespace core
} // namespace pcl_graph_denoise

/*
 * pcl_graph_denoise: graph-signal-processing point cloud denoising for PCL.
 * SPDX-License-Identifier: BSD-3-Clause
 */
#pragma once

/** \file graph.h
 *  \brief The point graph: a symmetric, weighted neighbourhood graph stored as
 *  CSR in a spatially coherent internal order, and how to build it.
 *
 *  This header is part of the PCL-independent numerical core: it sees points
 *  only as an N x 3 float matrix. Everything here throws std::invalid_argument
 *  on invalid parameters; the PCL adaptors turn that into PCL_ERROR.
 */

#include <Eigen/Core>

#include <cstddef>
#include <cstdint>
#include <vector>

namespace pcl_graph_denoise {
namespace core {

/** \brief Vertex index type of the graph (32 bits: at most 2^32 - 2 points; the largest
 *  value marks "no vertex"). */
using VertexIndex = std::uint32_t;

/** \brief Positions of N points, one per row, in the caller's units. */
using PointMatrix = Eigen::Matrix<float, Eigen::Dynamic, 3, Eigen::RowMajor>;

/** \brief A signal of three values per vertex (e.g. x, y, z), one row per vertex. */
using Signal3 = Eigen::Matrix<double, Eigen::Dynamic, 3, Eigen::RowMajor>;

/** \brief Symmetric weighted graph over a point set.
 *
 * Vertices are numbered in an internal, spatially coherent order (Morton / Z-order
 * of the positions), which keeps neighbours close in memory: sparse products over
 * this graph are several times faster than in scan or random order.
 * `order[v]` is the row of the caller's point matrix that vertex `v` stands for.
 *
 * Adjacency is stored once per direction in CSR form: the neighbours of vertex v are
 * `col[row_ptr[v] .. row_ptr[v+1])`, sorted by increasing index, with the Gaussian
 * weights `weight[...]` at the same positions. The matrix is exactly symmetric
 * (w_ij == w_ji, bit for bit) and has no self loops.
 */
struct PointGraph
{
  std::vector<std::uint64_t> row_ptr;  ///< N + 1 offsets into col / weight
  std::vector<VertexIndex> col;        ///< neighbour vertex of each stored entry
  std::vector<float> weight;           ///< w_ij = exp(-|p_i - p_j|^2 / (2 theta^2))
  std::vector<VertexIndex> order;      ///< order[v] = caller's row of vertex v
  double sigma = 0.0;                  ///< theta actually used for the weights
  /** Mean distance of a point to its k nearest neighbours, over the points whose own is
   *  at most 50 times the median's (isolated far points do not count). */
  double spacing = 0.0;

  /** \brief Number of vertices N. */
  std::size_t
  numVertices () const { return order.size (); }

  /** \brief Number of stored entries (twice the number of undirected edges). */
  std::size_t
  numEntries () const { return col.size (); }

  /** \brief Number of undirected edges, each counted once. */
  std::size_t
  numEdges () const { return col.size () / 2; }

  /** \brief Bytes held by the graph's arrays (its memory footprint). */
  std::size_t
  memoryBytes () const;
};

/** \brief Parameters of the symmetrised k-nearest-neighbour graph.
 *
 * Vertex i is linked to j when j is among the k nearest neighbours of i OR i is among
 * the k nearest neighbours of j (the paper's rule). A non-mutual edge is weighted
 * exactly like a mutual one: its weight depends on its length only, and an edge
 * found from both ends is stored once, not counted twice.
 */
struct KnnGraphParams
{
  /** Number of nearest neighbours searched per point (excluding the point itself).
   *  Valid: k >= 1. With fewer than k + 1 points, every point links to all others. */
  int k = 10;
  /** Gaussian kernel width theta, in the points' units. 0 (default) derives it from
   *  the data: theta = spacing / sqrt(2), spacing = mean k-NN distance (GSPBox's
   *  convention; PointGraph::spacing leaves out isolated far points), so the graph is
   *  invariant to the cloud's unit. Valid: >= 0, finite. */
  double sigma = 0.0;
  /** Worker threads; 0 = all hardware threads. The result does not depend on it. */
  int num_threads = 0;
  /** Bytes the graph may take at its peak (core::knnGraphMemory); 0 (default) = the
   *  machine's physical memory. A larger graph is refused before anything is allocated. */
  std::size_t memory_limit = 0;
};

/** \brief Parameters of the epsilon-radius graph (edge when |p_i - p_j| < epsilon). */
struct RadiusGraphParams
{
  /** Radius epsilon in the points' units. 0 (default) derives it from the data:
   *  epsilon = radius_factor * spacing, with spacing the median over the points of
   *  their mean distance to their `spacing_k` nearest neighbours (the median keeps
   *  far outliers from inflating it), taken over the distinct positions when there are
   *  exact copies (they do not make the surface denser). Valid: >= 0, finite. */
  double radius = 0.0;
  /** Kernel width theta; 0 (default) = sigma_factor * spacing. Valid: >= 0, finite. */
  double sigma = 0.0;
  /** Multiple of the spacing used for the default radius. Valid: > 0, finite. */
  double radius_factor = 2.0;
  /** Multiple of the spacing used for the default theta; the default 1/sqrt(2) is the
   *  k-NN graph's (GSPBox's) convention. Valid: > 0, finite. */
  double sigma_factor = 0.70710678118654752;
  /** Neighbours used to estimate the spacing. Valid: >= 1. */
  int spacing_k = 10;
  /** radiusGraphDegrees only: multiplier c of the normal-residual test, 0 (default) =
   *  no test. See RadiusDegrees::off_surface. Valid: >= 0, finite. */
  double residual_multiplier = 0.0;
  /** radiusGraphDegrees only: ratio r of the sparse-surface test, 0 (default) = no test.
   *  The points whose degree is below automaticDegreeThreshold (degrees, r) are tested;
   *  see RadiusDegrees::sparse_surface. Valid: >= 0, finite. */
  double sparse_surface_ratio = 0.0;
  /** radiusGraphDegrees only: the first `query_rows` rows of the points are the queries,
   *  the others are searched as neighbours only (as PCL's filters search the whole cloud
   *  for the points their indices name); 0 (default) = every row is a query. The
   *  spacing, the residual test's noise scale and every per-point output are then the
   *  queries' alone. Valid: <= the number of points. */
  std::size_t query_rows = 0;
  /** Worker threads; 0 = all hardware threads. The result does not depend on it. */
  int num_threads = 0;
};

/** \brief The widest extent of the points along an axis that the graphs take: the
 *  neighbour search's single-precision squared distances overflow (and lose every
 *  neighbour) beyond about 1.8e19. */
constexpr double kMaxPointExtent = 1e18;

/** \brief Build the symmetrised k-NN graph of the finite points in `points`.
 *  \throws std::invalid_argument on invalid parameters, non-finite points, more
 *  than 2^32 - 2 points, points spanning more than 1e18 units along an axis (the
 *  neighbour search's single-precision squared distances would overflow), or a graph
 *  whose estimated peak memory (core::knnGraphMemory) exceeds params.memory_limit
 *  (k is capped at N - 1, so a huge k asks for the complete graph). An empty point set gives an empty graph. */
PointGraph
buildKnnGraph (const PointMatrix &points, const KnnGraphParams &params = {});

/** \brief Parameters of the spatio-temporal k-NN graph of a sequence of frames (the
 *  paper's graph for time-varying clouds). */
struct SpatioTemporalGraphParams
{
  /** k1: nearest neighbours of each point in its own frame (excluding itself).
   *  Valid: >= 1; a frame of fewer than k1 + 1 points links all its points. */
  int k_spatial = 10;
  /** k2: nearest neighbours of each point in each other frame of the window. The paper
   *  suggests k1 > 2 k2. Valid: >= 0; 0 gives the frames' own k-NN graphs side by side. */
  int k_temporal = 3;
  /** Frames t - window ... t + window are linked to frame t. Valid: >= 0. */
  int window = 1;
  /** Kernel width theta, in the points' units; 0 (default) = the mean distance of a
   *  point to its k1 nearest neighbours in its own frame / sqrt(2), as for the static
   *  graph (GSPBox's convention). Valid: >= 0, finite. */
  double sigma = 0.0;
  /** Worker threads; 0 = all hardware threads. The result does not depend on it. */
  int num_threads = 0;
  /** Bytes the graph may take at its peak; 0 (default) = the machine's physical memory. */
  std::size_t memory_limit = 0;
};

/** \brief Build the spatio-temporal graph of a sequence of frames in one coordinate
 *  system: each point linked to its k1 nearest neighbours in its own frame and to its
 *  k2 nearest points in each other frame within the window, symmetrised as the static
 *  graph (an edge when either end found the other), Gaussian weights of the edge length.
 *  The vertices are all points of all frames; graph.order[v] numbers them in the
 *  concatenation of the frames (frame 0's rows first). Points do not correspond across
 *  frames; frames may differ in size or be empty. With one frame, or k2 = 0 and an
 *  explicit theta, the result is the static k-NN graph of each frame.
 *  \throws std::invalid_argument on invalid parameters, non-finite points, or more than
 *  2^32 - 2 points in all, or a graph above the memory limit (as buildKnnGraph). */
PointGraph
buildSpatioTemporalGraph (const std::vector<PointMatrix> &frames,
                          const SpatioTemporalGraphParams &params = {});

/** \brief Build the epsilon-radius graph of `points` (see RadiusGraphParams).
 *  \param[in] points the points, one per row (all finite).
 *  \param[in] params epsilon, theta and threads; zeros are derived from the data.
 *  \param[out] radius_used if not null, receives the epsilon actually used.
 *  \throws std::invalid_argument as buildKnnGraph (but for the memory check). */
PointGraph
buildRadiusGraph (const PointMatrix &points, const RadiusGraphParams &params = {},
                  double *radius_used = nullptr);

/** \brief Weighted degrees of the epsilon-radius graph, without storing the graph. */
struct RadiusDegrees
{
  /** Degree of each point, in the caller's row order (of the query rows only, with
   *  RadiusGraphParams::query_rows; so are the other per-point vectors). */
  std::vector<double> degree;
  double radius = 0.0;         ///< epsilon used
  double sigma = 0.0;          ///< theta used
  double spacing = 0.0;        ///< median mean k-NN distance (the derived scale)
  /** Each point's mean distance to its spacing_k nearest neighbours, in the caller's row
   *  order: how isolated it is, also where its degree is 0. */
  std::vector<float> mean_knn_distance;
  /** With RadiusGraphParams::residual_multiplier c > 0: 1 for the points off the surface
   *  their neighbours sample. Each point's epsilon-neighbours (itself excluded; its 256
   *  nearest where there are more) are
   *  fitted a plane (mean c_i, normal n_i the least-spread direction of their covariance),
   *  refitted up to 4 times without the neighbours farther than 3 spreads from it (so that
   *  a few outliers among them neither tilt it nor widen it). The point's residual
   *  r_i = |n_i . (p_i - c_i)| is the normal component of the random-walk Laplacian of the
   *  coordinates, ((I - D^-1 W) p)_i, with equal weights. The point is flagged when
   *  - r_i > c x max(s, s_i), s_i the RMS distance of the neighbours to the final plane
   *    and s the cloud's noise scale: the median residual / 0.6745 (a Gaussian's standard
   *    deviation), at least 0.01 spacing;
   *  - the same holds at c / 2 for the plane of all its neighbours: near a sharp edge or
   *    corner, or a step, the neighbours are far off any plane and keep it;
   *  - at most one neighbour is level with it (closer than r_i / 2 along n_i): a row or a
   *    layer of points off the plane, as a depth camera's quantisation steps, is kept.
   *  A point with fewer than 5 neighbours is never flagged. Empty when c = 0. */
  std::vector<std::uint8_t> off_surface;
  /** The global scale s of the residual test (0 without it). */
  double residual_scale = 0.0;
  /** With RadiusGraphParams::sparse_surface_ratio r > 0: 1 for the points whose degree is
   *  below automaticDegreeThreshold (degree, r) but that continue a surface sampled more
   *  sparsely than the rest of the cloud (a wall far from a laser scanner or a depth
   *  camera, whose spacing grows with the range, so that epsilon holds few or none of its
   *  points). The test grows from the cloud's typical points (degree at or above the
   *  threshold, mean_knn_distance at most 1.25 x spacing) along links j -> i, j among the
   *  spacing_k nearest distinct positions of i (copies count once, i's own position not
   *  at all), where i is at most 1.25 times as sparse as j (mean_knn_distance): density
   *  that changes gradually, as along a surface seen at a growing range. A point reached
   *  passes the growth on only when it lies on the plane of those neighbours: their
   *  smallest standard deviation at most 0.4 times their largest, and the point's distance
   *  to their plane at most 0.4 times the largest, or on their line (their middle standard
   *  deviation at most 0.1 times the largest, the point within 0.4 times it of the line).
   *  A point on such a line at most 1.25 times as sparse as the median of its neighbours
   *  starts a growth of its own: a far ring of a spinning scanner, whose nearest
   *  neighbours all lie on it, is out of reach of the rest. Uniform outliers stay
   *  unreached: their density drops at once from the surface's, and they lie on no plane
   *  (on the synthetic clouds of docs/evaluation.md section 4 the F1 scores did not change
   *  in the third decimal). Empty when r = 0. */
  std::vector<std::uint8_t> sparse_surface;
};

/** \brief The automatic degree threshold of an outlier test: `ratio` times the first
 *  quartile of `degree` (the inliers' typical degree, even with up to 25% outliers);
 *  when more than a quarter of the degrees are 0, the first quartile of the others, so
 *  that the points without neighbours are still below it. */
struct DegreeThreshold
{
  double threshold = 0.0;  ///< the threshold: ratio x the quartile
  /** The degrees that were 0 when they were more than a quarter (0 otherwise). When
   *  every degree is 0 (with a ratio > 0), all of them, and the threshold is 0: there is
   *  nothing to derive it from. */
  std::size_t without_neighbour = 0;
};

/** \brief See DegreeThreshold. 0 for no degrees. \throws std::invalid_argument for a
 *  negative or non-finite ratio. */
DegreeThreshold
automaticDegreeThreshold (const std::vector<double> &degree, double ratio);

/** \brief The weighted degree of every point in the epsilon-radius graph of `points`
 *  (the same graph and weights as buildRadiusGraph), computed while searching: the
 *  edges are never stored, so memory stays at O(N) for any radius.
 *  \throws std::invalid_argument as buildKnnGraph. */
RadiusDegrees
radiusGraphDegrees (const PointMatrix &points, const RadiusGraphParams &params = {});

/** \brief The distinct positions of a point set: rows with equal x, y and z are one. */
struct DistinctPoints
{
  /** One row per distinct position, in the order of their first rows. */
  PointMatrix points;
  /** For each row of the input, the row of `points` at its position. */
  std::vector<VertexIndex> of_row;
  /** Input rows that repeat an earlier row's position (0: `points` is the input). */
  std::size_t copies = 0;
};

/** \brief Merges the rows of `points` at the same position (exact float equality, -0 ==
 *  0): a point sampled several times is one vertex of a graph, and every copy gets its
 *  result. Without copies, `points` is left empty (the input is the answer) and `of_row`
 *  is the identity. */
DistinctPoints
distinctPoints (const PointMatrix &points);

/** \brief Gaussian edge weight exp(-d2 / (2 sigma^2)) of a squared length d2, in
 *  single precision as the graph stores it (the graphs compute the same weights
 *  vectorised, to within an ulp). Coincident points (d2 == 0) weigh 1 for any sigma;
 *  with sigma == 0 every other edge weighs 0 (the limit of the kernel), as does every
 *  edge whose weight would be below the smallest normal float (d2 > 174 sigma^2). */
float
gaussianWeight (double squared_distance, double sigma);

} // namespace core
} // namespace pcl_graph_denoise

/*
 * pcl_graph_denoise: graph-signal-processing point cloud denoising for PCL.
 * SPDX-License-Identifier: BSD-3-Clause
 */
#pragma once

/* Private to the core: the coarse part of the conjugate gradient's preconditioner for
 * (I + 2 gamma L), on aggregates of consecutive vertices.
 *
 * The graph's vertices are stored in a spatially coherent (Morton) order, so a run of
 * consecutive vertices is a small patch of the surface. Each run of kFirstAggregate
 * linked vertices becomes one vertex of a coarse graph, whose operator is the Galerkin product
 * P^T (I + 2 gamma L) P with P constant on each run: a diagonal of the runs' sizes plus
 * 2 gamma times the Laplacian of the summed weights between runs. The same is done on the
 * coarse graph with runs of kAggregate vertices, and so on until at most kCoarsest
 * vertices remain, which are solved exactly (dense Cholesky).
 *
 * The conjugate gradient applies z = D^-1 r + P V (P^T r): Jacobi on the graph itself
 * plus a symmetric V-cycle (damped Jacobi before and after each coarse correction) on the
 * coarse levels. The part on the graph costs no product with it; the coarse levels hold
 * about a sixteenth of its vertices. Jacobi alone leaves the smooth modes, whose
 * eigenvalues 1 + 2 gamma lambda lie near the bottom of the spectrum, slowest to converge;
 * the coarse levels take them. On a noisy 1,000,000-point sphere it halves the iterations
 * (docs/evaluation.md, section 5). Everything is a fixed function of the graph: the result
 * does not depend on the number of threads. */

#include <pcl_graph_denoise/core/graph.h>

#include <Eigen/Cholesky>
#include <Eigen/Core>

#include <cstddef>
#include <cstdint>
#include <vector>

namespace pcl_graph_denoise {
namespace core {
namespace detail {

class AggregationPreconditioner
{
public:
  /** Vertices of the graph per vertex of the first coarse level. */
  static constexpr std::size_t kFirstAggregate = 16;
  /** Vertices of a coarse level per vertex of the next. */
  static constexpr std::size_t kAggregate = 8;
  /** The coarsest level has at most this many vertices, solved exactly. */
  static constexpr std::size_t kCoarsest = 256;

  using Coarse3 = Eigen::Matrix<double, Eigen::Dynamic, 3, Eigen::RowMajor>;

  /** Builds the coarse levels of (I + g2 L) for the graph (g2 = 2 gamma; degree: its
   *  weighted degrees). A vertex without links (degree 0) belongs to no aggregate: its
   *  row of the system is the identity's and its solution exactly its right-hand side,
   *  which a coarse correction shared with its neighbours in the order would blur. */
  AggregationPreconditioner (const PointGraph &graph, const std::vector<double> &degree,
                             double g2, int num_threads);

  /** 1 for the vertices of the graph that belong to an aggregate (those with links):
   *  the residual is restricted from them and the coarse correction prolonged to them. */
  const std::vector<std::uint8_t> &
  linked () const
  {
    return linked_;
  }

  /** Vertices of the first coarse level: ceil(N / kFirstAggregate). */
  std::size_t
  coarseSize () const
  {
    return levels_.empty () ? 0 : levels_.front ().size ();
  }

  /** zc = V rc: the coarse levels' symmetric V-cycle applied to a restricted residual
   *  (row a of rc: the sum of the residual over aggregate a). Not for concurrent calls:
   *  it works in buffers of its own. */
  void
  applyCoarse (const Coarse3 &rc, Coarse3 &zc) const;

private:
  /** One coarse level: its operator in CSR (entries between distinct vertices, weights
   *  summed) with the diagonal of I + g2 L restricted to it. */
  struct Level
  {
    std::vector<std::uint64_t> row_ptr;
    std::vector<VertexIndex> col;
    std::vector<float> weight;
    std::vector<double> diagonal;  ///< size of the aggregate + g2 * weighted degree
    mutable Coarse3 z, rc, zc;  ///< work space of the V-cycle at this level
    std::size_t
    size () const
    {
      return diagonal.size ();
    }
  };

  void
  cycle (std::size_t l, const Coarse3 &r, Coarse3 &z) const;

  double g2_;
  int num_threads_;
  std::vector<std::uint8_t> linked_;
  std::vector<Level> levels_;
  Eigen::LLT<Eigen::MatrixXd> coarsest_;
};

} // namespace detail
} // namespace core
} // namespace pcl_graph_denoise

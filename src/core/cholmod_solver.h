/*
 * pcl_graph_denoise: graph-signal-processing point cloud denoising for PCL.
 * SPDX-License-Identifier: BSD-3-Clause
 */
#pragma once

/* Private to the core: the exact Tikhonov solve through SuiteSparse's CHOLMOD, kept
 * out of every public header. */

#include <pcl_graph_denoise/core/graph.h>

#include <memory>

namespace pcl_graph_denoise {
namespace core {
namespace detail {

/** The sparse Cholesky factorisation of I + 2 gamma L, computed once and solved for any
 *  number of right-hand sides. */
class CholmodFactor
{
public:
  /** \throws std::runtime_error when CHOLMOD fails (e.g. out of memory) or the system is
   *  not numerically positive definite (gamma x degree too large for double precision). */
  CholmodFactor (const PointGraph &graph, double gamma);
  ~CholmodFactor ();
  CholmodFactor (const CholmodFactor &) = delete;
  CholmodFactor &
  operator= (const CholmodFactor &) = delete;

  /** x = (I + 2 gamma L)^-1 f. Not for concurrent calls.
   *  \throws std::runtime_error when CHOLMOD fails. */
  Signal3
  solve (const Signal3 &f) const;

private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

} // namespace detail
} // namespace core
} // namespace pcl_graph_denoise

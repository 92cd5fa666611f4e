/*
 * pcl_graph_denoise: graph-signal-processing point cloud denoising for PCL.
 * SPDX-License-Identifier: BSD-3-Clause
 */
#include "cholmod_solver.h"

#include <cholmod.h>

#include <limits>
#include <stdexcept>
#include <string>

namespace pcl_graph_denoise {
namespace core {
namespace detail {

namespace {

/** CHOLMOD's workspace, started and finished with the factorisation's owner. */
class Common
{
public:
  Common () { cholmod_l_start (&common_); }
  ~Common () { cholmod_l_finish (&common_); }
  Common (const Common &) = delete;
  Common &
  operator= (const Common &) = delete;
  cholmod_common *
  get () { return &common_; }

private:
  cholmod_common common_;
};

void
check (bool ok, cholmod_common *c, const char *what)
{
  if (!ok || c->status < CHOLMOD_OK)
    throw std::runtime_error (std::string ("CHOLMOD failed in ") + what + " (status " +
                              std::to_string (c->status) + ")");
}

} // namespace

struct CholmodFactor::Impl
{
  Common common;
  cholmod_factor *factor = nullptr;
  std::size_t n = 0;

  ~Impl () { cholmod_l_free_factor (&factor, common.get ()); }
};

CholmodFactor::CholmodFactor (const PointGraph &graph, double gamma) : impl_ (new Impl)
{
  const std::size_t n = graph.numVertices ();
  impl_->n = n;
  cholmod_common *c = impl_->common.get ();

  // The lower triangle (stype -1) in compressed columns: column i holds the diagonal
  // 1 + 2 gamma d_i, then -2 gamma w_ij for the neighbours j > i (the upper part of CSR
  // row i, which is sorted).
  std::size_t nnz = n;
  for (std::size_t i = 0; i < n; ++i)
    for (std::uint64_t e = graph.row_ptr[i]; e < graph.row_ptr[i + 1]; ++e)
      nnz += graph.col[e] > i;
  cholmod_sparse *a = cholmod_l_allocate_sparse (n, n, nnz, 1, 1, -1, CHOLMOD_REAL, c);
  check (a != nullptr, c, "allocate_sparse");
  auto *cp = static_cast<SuiteSparse_long *> (a->p);
  auto *ci = static_cast<SuiteSparse_long *> (a->i);
  auto *cx = static_cast<double *> (a->x);
  SuiteSparse_long pos = 0;
  for (std::size_t i = 0; i < n; ++i)
  {
    cp[i] = pos;
    double degree = 0.0;
    for (std::uint64_t e = graph.row_ptr[i]; e < graph.row_ptr[i + 1]; ++e)
      degree += graph.weight[e];
    ci[pos] = static_cast<SuiteSparse_long> (i);
    cx[pos++] = 1.0 + 2.0 * gamma * degree;
    for (std::uint64_t e = graph.row_ptr[i]; e < graph.row_ptr[i + 1]; ++e)
      if (graph.col[e] > i)
      {
        ci[pos] = graph.col[e];
        cx[pos++] = -2.0 * gamma * graph.weight[e];
      }
  }
  cp[n] = pos;

  impl_->factor = cholmod_l_analyze (a, c);
  const bool analysed = impl_->factor != nullptr && c->status >= CHOLMOD_OK;
  // A huge gamma x degree makes I + 2 gamma L numerically singular: CHOLMOD then only
  // warns (CHOLMOD_NOT_POSDEF, factor->minor < n) and its solve would be inf or NaN.
  const bool factorised_any =
      analysed && cholmod_l_factorize (a, impl_->factor, c) && c->status >= CHOLMOD_OK;
  const bool not_positive_definite = factorised_any && impl_->factor->minor < n;
  const int status = c->status;
  cholmod_l_free_sparse (&a, c);
  if (not_positive_definite)
    throw std::runtime_error ("CHOLMOD: the Tikhonov system is not numerically positive "
                              "definite (gamma x degree too large for double precision)");
  if (!factorised_any)
    throw std::runtime_error ("CHOLMOD could not factorise the Tikhonov system (status " +
                              std::to_string (status) + ")");
}

CholmodFactor::~CholmodFactor () = default;

Signal3
CholmodFactor::solve (const Signal3 &f) const
{
  const std::size_t n = impl_->n;
  cholmod_common *c = impl_->common.get ();
  Signal3 out (static_cast<Eigen::Index> (n), 3);  // before CHOLMOD's buffers: it may throw
  cholmod_dense *b = cholmod_l_allocate_dense (n, 3, n, CHOLMOD_REAL, c);
  check (b != nullptr, c, "allocate_dense");
  auto *bx = static_cast<double *> (b->x);
  for (std::size_t i = 0; i < n; ++i)
    for (int col = 0; col < 3; ++col)
      bx[col * n + i] = f (i, col);
  cholmod_dense *x = cholmod_l_solve (CHOLMOD_A, impl_->factor, b, c);
  const bool solved = x != nullptr && c->status >= CHOLMOD_OK;
  if (solved)
  {
    const auto *xx = static_cast<const double *> (x->x);
    for (std::size_t i = 0; i < n; ++i)
      for (int col = 0; col < 3; ++col)
        out (i, col) = xx[col * n + i];
  }
  const int status = c->status;
  cholmod_l_free_dense (&x, c);
  cholmod_l_free_dense (&b, c);
  if (!solved)
    throw std::runtime_error ("CHOLMOD could not solve the Tikhonov system (status " +
                              std::to_string (status) + ")");
  return out;
}

} // namespace detail
} // namespace core
} // namespace pcl_graph_denoise

/*
 * pcl_graph_denoise: graph-signal-processing point cloud denoising for PCL.
 * SPDX-License-Identifier: BSD-3-Clause
 *
 * The Tikhonov and total-variation solvers and the noise estimate, verified against
 * independent references: a full eigendecomposition, CHOLMOD, a second TV method run
 * long, and random perturbations of the minimiser; and the conjugate gradient's coarse
 * levels (the core's private AggregationPreconditioner) against dense Galerkin products
 * and plain Jacobi-preconditioned CG.
 */
#include <pcl_graph_denoise/core/graph.h>
#include <pcl_graph_denoise/core/noise_level.h>
#include <pcl_graph_denoise/core/operators.h>
#include <pcl_graph_denoise/core/solvers.h>

#include "aggregation.h"
#include "synthetic.h"
#include "wide_kernels.h"

#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <random>
#include <type_traits>
#include <stdexcept>

using namespace pcl_graph_denoise;
using namespace pcl_graph_denoise::core;

namespace {

using synthetic::toMatrix;

/** The points of a graph's cloud in its vertex order. */
Signal3
vertexSignal (const PointGraph &g, const PointMatrix &points)
{
  Signal3 f (g.numVertices (), 3);
  for (std::size_t v = 0; v < g.numVertices (); ++v)
    f.row (v) = points.row (g.order[v]).cast<double> ();
  return f;
}

Eigen::MatrixXd
denseLaplacian (const PointGraph &g)
{
  const auto n = static_cast<Eigen::Index> (g.numVertices ());
  Eigen::MatrixXd l = Eigen::MatrixXd::Zero (n, n);
  for (Eigen::Index i = 0; i < n; ++i)
    for (auto e = g.row_ptr[i]; e < g.row_ptr[i + 1]; ++e)
    {
      l (i, g.col[e]) -= g.weight[e];
      l (i, i) += g.weight[e];
    }
  return l;
}

/** A small noisy sphere and its graph. */
struct Problem
{
  explicit Problem (std::size_t n, double noise = 0.02, std::uint64_t seed = 3, int k = 10)
  : points (toMatrix (synthetic::noisySphere (n, 1.0, noise, seed))),
    graph (buildKnnGraph (points, knn (k))), f (vertexSignal (graph, points))
  {}
  static KnnGraphParams
  knn (int k)
  {
    KnnGraphParams params;
    params.k = k;
    return params;
  }
  PointMatrix points;
  PointGraph graph;
  Signal3 f;
};

/** A second TV method, for reference: FISTA on the dual problem
 *  min_y 1/2 |f - grad^T y|^2 subject to |y_e| <= gamma, with x = f - grad^T y. */
Signal3
dualFista (const PointGraph &g, const Signal3 &f, double gamma, TotalVariationNorm norm,
           int iterations)
{
  const auto degree = weightedDegree (g);
  const double lipschitz = 2.0 * *std::max_element (degree.begin (), degree.end ());
  Signal3 y = Signal3::Zero (g.numEdges (), 3), z = y, y_old, gty, grad;
  double t = 1.0;
  for (int it = 0; it < iterations; ++it)
  {
    applyGradientAdjoint (g, z, gty);
    applyGradient (g, f - gty, grad);  // minus the gradient of the dual objective
    y_old = y;
    y = z + grad / lipschitz;
    for (Eigen::Index e = 0; e < y.rows (); ++e)
    {
      if (norm == TotalVariationNorm::ISOTROPIC)
      {
        const double length = y.row (e).norm ();
        if (length > gamma)
          y.row (e) *= gamma / length;
      }
      else
        y.row (e) = y.row (e).cwiseMax (-gamma).cwiseMin (gamma);
    }
    const double t_next = 0.5 * (1.0 + std::sqrt (1.0 + 4.0 * t * t));
    z = y + ((t - 1.0) / t_next) * (y - y_old);
    t = t_next;
  }
  applyGradientAdjoint (g, y, gty);
  return f - gty;
}

} // namespace

TEST (Tikhonov, MatchesTheSpectralFilter)
{
  const Problem p (300);
  const double gamma = 0.7;
  Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig (denseLaplacian (p.graph));
  const Eigen::VectorXd h = (1.0 + 2.0 * gamma * eig.eigenvalues ().array ()).inverse ();
  const Eigen::MatrixXd reference =
      eig.eigenvectors () * h.asDiagonal () * eig.eigenvectors ().transpose () * p.f;
  TikhonovParams params;
  params.tolerance = 1e-12;
  SolverReport report;
  const Signal3 x = solveTikhonov (p.graph, p.f, gamma, params, &report);
  EXPECT_TRUE (report.converged);
  EXPECT_LT ((x - reference).cwiseAbs ().maxCoeff (), 1e-9);
  params.solver = TikhonovSolver::CHOLMOD;
  EXPECT_LT ((solveTikhonov (p.graph, p.f, gamma, params) - reference).cwiseAbs ().maxCoeff (),
             1e-9);
}

TEST (Tikhonov, ConjugateGradientAgreesWithCholmod)
{
  const Problem p (20000, 0.01);
  const double gamma = 5.0;
  TikhonovParams cg, direct;
  cg.tolerance = 1e-10;
  direct.solver = TikhonovSolver::CHOLMOD;
  SolverReport report;
  const Signal3 a = solveTikhonov (p.graph, p.f, gamma, cg, &report);
  const Signal3 b = solveTikhonov (p.graph, p.f, gamma, direct);
  EXPECT_TRUE (report.converged);
  EXPECT_GT (report.iterations, 1);
  EXPECT_LT ((a - b).cwiseAbs ().maxCoeff (), 1e-8);
}

TEST (Tikhonov, ReportsTheResidualOfItsResultInDoublePrecision)
{
  // The conjugate gradient runs its vectors in single precision first: its report must
  // still be the residual of the returned x, computed here in double, and within the
  // tolerance; at a tolerance below single precision's reach the double-precision phase
  // takes it there. Since I + 2 gamma L >= I, |x - x*| <= |residual| (CHOLMOD's x*).
  const Problem p (20000, 0.01);
  const double gamma = 20.0;
  TikhonovParams direct;
  direct.solver = TikhonovSolver::CHOLMOD;
  const Signal3 exact = solveTikhonov (p.graph, p.f, gamma, direct);
  const double scale = (p.f.rowwise () - p.f.colwise ().mean ()).norm ();
  for (const double tolerance : {1e-3, 1e-4, 1e-7, 1e-11})
  {
    TikhonovParams params;
    params.tolerance = tolerance;
    SolverReport report;
    const Signal3 x = solveTikhonov (p.graph, p.f, gamma, params, &report);
    Signal3 lx;
    applyLaplacian (p.graph, x, lx);
    const double residual = (x + 2.0 * gamma * lx - p.f).norm () / scale;
    EXPECT_TRUE (report.converged) << tolerance;
    EXPECT_LE (residual, tolerance) << tolerance;
    EXPECT_NEAR (report.residual, residual, 1e-6 * residual + 1e-15) << tolerance;
    EXPECT_LE ((x - exact).norm () / scale, tolerance) << tolerance;
  }
}

TEST (Tikhonov, ASignalBeyondSinglePrecisionsRangeIsSolvedInDouble)
{
  // The solve is linear in f: a signal scaled by 1e38 (finite in single precision, but its
  // residual is not) gives the scaled solution, from the phase in double precision.
  const Problem p (5000);
  const double gamma = 50.0;
  const double huge = 1e38;
  SolverReport unit_report, huge_report;
  const Signal3 unit = solveTikhonov (p.graph, p.f, gamma, {}, &unit_report);
  const Signal3 scaled = solveTikhonov (p.graph, Signal3 (huge * p.f), gamma, {}, &huge_report);
  ASSERT_TRUE (scaled.allFinite ());
  EXPECT_TRUE (unit_report.converged);
  EXPECT_TRUE (huge_report.converged);
  EXPECT_LT ((scaled / huge - unit).cwiseAbs ().maxCoeff (), 1e-4);
}

TEST (Tikhonov, ZeroGammaIsTheIdentityAndTheMeanIsKept)
{
  const Problem p (2000);
  EXPECT_TRUE (solveTikhonov (p.graph, p.f, 0.0) == p.f);
  TikhonovParams tight;
  tight.tolerance = 1e-10;
  const Signal3 x = solveTikhonov (p.graph, p.f, 3.0, tight);
  // Exact in exact arithmetic (L 1 = 0); the preconditioned CG keeps it to its tolerance.
  EXPECT_LT ((x.colwise ().mean () - p.f.colwise ().mean ()).norm (), 1e-9);
  EXPECT_LT (x.colwise ().squaredNorm ().sum (), p.f.colwise ().squaredNorm ().sum ());
}

TEST (Tikhonov, ResultDoesNotDependOnThreadCount)
{
  const Problem p (30000);
  TikhonovParams one, two;
  one.num_threads = 1;
  two.num_threads = 2;
  EXPECT_TRUE (solveTikhonov (p.graph, p.f, 2.0, one) == solveTikhonov (p.graph, p.f, 2.0, two));
}

TEST (Tikhonov, IterationCapIsReported)
{
  const Problem p (5000);
  TikhonovParams params;
  params.max_iterations = 2;
  params.tolerance = 1e-14;
  SolverReport report;
  const Signal3 x = solveTikhonov (p.graph, p.f, 50.0, params, &report);
  EXPECT_FALSE (report.converged);
  EXPECT_EQ (report.iterations, 2);
  EXPECT_GT (report.residual, 1e-14);
  EXPECT_TRUE (x.allFinite ());
  // No iteration allowed: the start, f, with its residual.
  params.max_iterations = 0;
  SolverReport none;
  EXPECT_TRUE (solveTikhonov (p.graph, p.f, 50.0, params, &none) == p.f);
  EXPECT_FALSE (none.converged);
  EXPECT_EQ (none.iterations, 0);
  EXPECT_GT (none.residual, report.residual);
}

TEST (Tikhonov, AFarPointDoesNotLoosenTheStoppingTest)
{
  // A noisy plane, with and without a point 10^6 units away (alone in the graph): the
  // plane's solution is the same to the tolerance. The residual was relative to the
  // centred norm of the whole signal, which the far point makes 10^6: no iteration ran.
  std::mt19937 rng (3);
  std::normal_distribution<float> noise (0.0f, 0.003f);
  PointMatrix plane (900, 3), both (901, 3);
  for (int i = 0; i < 900; ++i)
    plane.row (i) << 0.01f * float (i % 30), 0.01f * float (i / 30), noise (rng);
  both.topRows (900) = plane;
  both.row (900) << 1e6f, 0.1f, 0.0f;
  KnnGraphParams params;
  params.sigma = 0.01;
  const PointGraph g_plane = buildKnnGraph (plane, params), g_both = buildKnnGraph (both, params);
  SolverReport report_plane, report_both;
  const Signal3 x_plane = solveTikhonov (g_plane, vertexSignal (g_plane, plane), 2.0, {}, &report_plane);
  const Signal3 x_both = solveTikhonov (g_both, vertexSignal (g_both, both), 2.0, {}, &report_both);
  EXPECT_GT (report_both.iterations, report_plane.iterations / 2);
  const Signal3 f_both = vertexSignal (g_both, both);
  double moved = 0.0, differ = 0.0;
  for (std::size_t v = 0; v < g_both.numVertices (); ++v)
  {
    const std::size_t i = g_both.order[v];
    if (i == 900)
    {
      EXPECT_EQ (x_both.row (v), f_both.row (v));  // alone: where it was
      continue;
    }
    const auto w = std::find (g_plane.order.begin (), g_plane.order.end (), VertexIndex (i)) -
                   g_plane.order.begin ();
    moved = std::max (moved, (x_both.row (v) - f_both.row (v)).norm ());
    differ = std::max (differ, (x_both.row (v) - x_plane.row (w)).norm ());
  }
  EXPECT_GT (moved, 0.003);
  EXPECT_LT (differ, 1e-4);
}

TEST (Tikhonov, TwoClustersFarApartAreEachSolvedAsAlone)
{
  // Two equal noisy planes D apart, each a component of the graph: each is solved as if
  // alone. The scale of the stopping test was the whole signal's centred norm, which the
  // distance makes about D sqrt(N) (unlike a single far point, two equal clusters also
  // move the median): at D = 10^3 three iterations ran, at 10^4 one (found by a helper's
  // audit); it is now centred on each component's mean.
  std::mt19937 rng (5);
  std::normal_distribution<float> noise (0.0f, 0.003f);
  PointMatrix plane (900, 3);
  for (int i = 0; i < 900; ++i)
    plane.row (i) << 0.01f * float (i % 30), 0.01f * float (i / 30), noise (rng);
  KnnGraphParams params;
  params.sigma = 0.01;
  const PointGraph g_plane = buildKnnGraph (plane, params);
  SolverReport report_plane;
  const Signal3 x_plane =
      solveTikhonov (g_plane, vertexSignal (g_plane, plane), 2.0, {}, &report_plane);
  ASSERT_GT (report_plane.iterations, 5);
  for (const float distance : {1e3f, 1e4f})
  {
    PointMatrix both (1800, 3);
    both.topRows (900) = plane;
    both.bottomRows (900) = plane;
    both.bottomRows (900).col (0).array () += distance;
    const PointGraph g_both = buildKnnGraph (both, params);
    SolverReport report_both;
    const Signal3 x_both =
        solveTikhonov (g_both, vertexSignal (g_both, both), 2.0, {}, &report_both);
    EXPECT_GE (report_both.iterations, report_plane.iterations - 1) << "D = " << distance;
    double differ = 0.0;
    for (std::size_t v = 0; v < g_both.numVertices (); ++v)
    {
      const std::size_t i = g_both.order[v];
      if (i >= 900)
        continue;  // the far copy's coordinates are rounded at D in single precision
      const auto w = std::find (g_plane.order.begin (), g_plane.order.end (), VertexIndex (i)) -
                     g_plane.order.begin ();
      differ = std::max (differ, (x_both.row (v) - x_plane.row (w)).norm ());
    }
    EXPECT_LT (differ, 1e-4) << "D = " << distance;
  }
}

TEST (Tikhonov, MostlyCoincidentRowsStillConverge)
{
  // Two thirds of the rows at one position: the robust scale of the stopping test is 0
  // there, and the centred norm takes over (else nothing but an exact 0 would stop it).
  std::mt19937 rng (4);
  std::uniform_real_distribution<float> u (-1.0f, 1.0f);
  PointMatrix p (900, 3);
  for (int i = 0; i < 900; ++i)
    p.row (i) << (i < 600 ? Eigen::RowVector3f::Zero () : Eigen::RowVector3f (u (rng), u (rng), 0.1f * u (rng)));
  const PointGraph g = buildKnnGraph (p);
  SolverReport report;
  const Signal3 x = solveTikhonov (g, vertexSignal (g, p), 1.0, {}, &report);
  EXPECT_TRUE (report.converged);
  EXPECT_LT (report.iterations, 200);
  EXPECT_TRUE (x.allFinite ());
}

TEST (Tikhonov, NeverReturnsAResultFarOutsideTheInputsBoundingBox)
{
  // (I + 2 gamma L)^-1 has no negative entry and rows summing to 1: the solution lies in
  // f's bounding box. Where gamma is too large for double precision (from about 1e20 here)
  // conjugate gradients wandered to 1e11 on this unit sphere; the solver now throws
  // instead of returning such an iterate.
  const Problem p (1500);
  const Eigen::RowVector3d low = p.f.colwise ().minCoeff (), high = p.f.colwise ().maxCoeff ();
  const double side = (high - low).maxCoeff ();
  for (const double gamma : {1e3, 1e12, 1e20, 1e30, 1e300})
  {
    TikhonovParams params;
    params.max_iterations = 2000;
    Signal3 x;
    try
    {
      x = solveTikhonov (p.graph, p.f, gamma, params);
    }
    catch (const std::runtime_error &e)
    {
      EXPECT_GE (gamma, 1e15) << "a moderate gamma must solve: " << e.what ();
      EXPECT_NE (std::string (e.what ()).find ("gamma"), std::string::npos) << e.what ();
      continue;
    }
    ASSERT_TRUE (x.allFinite ()) << "gamma " << gamma;
    EXPECT_LE ((low - x.colwise ().minCoeff ()).maxCoeff (), 1e-3 * side) << "gamma " << gamma;
    EXPECT_LE ((x.colwise ().maxCoeff () - high).maxCoeff (), 1e-3 * side) << "gamma " << gamma;
  }
}

/** Jacobi-preconditioned CG in double precision, written out here as the reference the
 *  solver's coarse levels are measured against: iterations until the residual of
 *  (I + g2 L) x = f is at most `target`. */
int
jacobiIterations (const PointGraph &g, const Signal3 &f, double g2, double target)
{
  const std::vector<double> degree = weightedDegree (g);
  const auto n = static_cast<Eigen::Index> (g.numVertices ());
  const Eigen::ArrayXd inverse =
      1.0 / (1.0 + g2 * Eigen::Map<const Eigen::ArrayXd> (degree.data (), n));
  const auto product = [&] (const Signal3 &v) {
    Signal3 lv (n, 3);
    applyLaplacian (g, v, lv);
    return Signal3 (v + g2 * lv);
  };
  Signal3 x = f, r = f - product (f);
  Signal3 z = inverse.matrix ().asDiagonal () * r, p = z;
  Eigen::Array3d rz = (r.array () * z.array ()).colwise ().sum ().transpose ();
  int it = 0;
  while (r.norm () > target && it < 10000)
  {
    const Signal3 q = product (p);
    for (int c = 0; c < 3; ++c)
    {
      const double alpha = rz[c] / p.col (c).dot (q.col (c));
      x.col (c) += alpha * p.col (c);
      r.col (c) -= alpha * q.col (c);
    }
    z = inverse.matrix ().asDiagonal () * r;
    for (int c = 0; c < 3; ++c)
    {
      const double next = r.col (c).dot (z.col (c));
      p.col (c) = z.col (c) + (next / rz[c]) * p.col (c);
      rz[c] = next;
    }
    ++it;
  }
  return it;
}

TEST (Tikhonov, CoarseLevelsCutTheIterationsOfJacobiPreconditioning)
{
  // At the filters' strengths (2 gamma times the mean degree of a few hundred) Jacobi
  // alone leaves the smooth directions slowest; the coarse levels take them (here 56
  // iterations instead of 106, and 95 instead of 250). Both solves are taken to the same
  // residual, the one the solver stopped at.
  const Problem p (50000, 0.01);
  const std::vector<double> degree = weightedDegree (p.graph);
  double mean_degree = 0.0;
  for (double d : degree)
    mean_degree += d / double (degree.size ());
  for (const double strength : {300.0, 1500.0})
  {
    const double gamma = strength / (2.0 * mean_degree);
    SolverReport report;
    const Signal3 x = solveTikhonov (p.graph, p.f, gamma, {}, &report);
    ASSERT_TRUE (report.converged);
    Signal3 lx (x.rows (), 3);
    applyLaplacian (p.graph, x, lx);
    const double reached = (p.f - x - 2.0 * gamma * lx).norm ();
    const int jacobi = jacobiIterations (p.graph, p.f, 2.0 * gamma, reached);
    EXPECT_LE (report.iterations, 0.6 * jacobi)
        << "2 gamma d = " << strength << ": " << report.iterations << " iterations against "
        << jacobi << " of Jacobi alone";
  }
}

namespace aggregation {

using detail::AggregationPreconditioner;
using Coarse3 = AggregationPreconditioner::Coarse3;

/** The dense prolongation: column a is 1 on the linked vertices of aggregate a. */
Eigen::MatrixXd
prolongation (const PointGraph &g, const std::vector<double> &degree)
{
  const auto n = static_cast<Eigen::Index> (g.numVertices ());
  const Eigen::Index block = AggregationPreconditioner::kFirstAggregate;
  Eigen::MatrixXd p = Eigen::MatrixXd::Zero (n, (n + block - 1) / block);
  for (Eigen::Index v = 0; v < n; ++v)
    p (v, v / block) = degree[v] > 0.0 ? 1.0 : 0.0;
  return p;
}

} // namespace aggregation

TEST (AggregationPreconditioner, OneCoarseLevelSolvesTheGalerkinSystemExactly)
{
  // 1,500 sphere points and one far point (alone: no weight survives): 94 aggregates,
  // few enough for the dense solve, so the coarse correction is (P^T A P)^-1 rc exactly,
  // with P constant on each aggregate's linked vertices and zero on the far point.
  using namespace aggregation;
  PointMatrix points = toMatrix (synthetic::noisySphere (1500, 1.0, 0.02, 5));
  points.conservativeResize (1501, 3);
  points.row (1500) << 1e4f, 0.0f, 0.0f;
  const PointGraph g = buildKnnGraph (points, KnnGraphParams ());
  const std::vector<double> degree = weightedDegree (g);
  ASSERT_EQ (std::count (degree.begin (), degree.end (), 0.0), 1);
  const double g2 = 40.0;
  const AggregationPreconditioner pre (g, degree, g2, 2);
  ASSERT_EQ (pre.coarseSize (), 94u);
  for (std::size_t v = 0; v < g.numVertices (); ++v)
    EXPECT_EQ (pre.linked ()[v], degree[v] > 0.0 ? 1 : 0);
  const Eigen::MatrixXd p = prolongation (g, degree);
  const auto n = static_cast<Eigen::Index> (g.numVertices ());
  const Eigen::MatrixXd a = Eigen::MatrixXd::Identity (n, n) + g2 * denseLaplacian (g);
  // The aggregate of the far point alone would be empty; it shares its aggregate here,
  // so every column of P has a linked vertex and P^T A P is positive definite.
  const Eigen::MatrixXd galerkin = p.transpose () * a * p;
  std::mt19937 rng (7);
  std::normal_distribution<double> normal;
  Coarse3 rc (94, 3), zc;
  for (Eigen::Index i = 0; i < rc.size (); ++i)
    rc.data ()[i] = normal (rng);
  pre.applyCoarse (rc, zc);
  const Eigen::MatrixXd exact = galerkin.ldlt ().solve (Eigen::MatrixXd (rc));
  EXPECT_LT ((Eigen::MatrixXd (zc) - exact).norm (), 1e-6 * exact.norm ());
}

TEST (AggregationPreconditioner, TheVCycleIsSymmetricPositiveAndThreadIndependent)
{
  // 100,000 points: coarse levels of 6,250 (built in two tasks), 782 and 98 vertices. The
  // conjugate gradient needs a symmetric positive definite preconditioner, the same on
  // any thread count.
  using namespace aggregation;
  const Problem p (100000, 0.01);
  const std::vector<double> degree = weightedDegree (p.graph);
  const AggregationPreconditioner one (p.graph, degree, 100.0, 1), two (p.graph, degree, 100.0, 2);
  const auto m = static_cast<Eigen::Index> (one.coarseSize ());
  ASSERT_EQ (m, 6250);
  std::mt19937 rng (9);
  std::normal_distribution<double> normal;
  const auto random = [&] () {
    Coarse3 r (m, 3);
    for (Eigen::Index i = 0; i < r.size (); ++i)
      r.data ()[i] = normal (rng);
    return r;
  };
  for (int trial = 0; trial < 5; ++trial)
  {
    const Coarse3 a = random (), b = random ();
    Coarse3 va, vb, va2;
    one.applyCoarse (a, va);
    one.applyCoarse (b, vb);
    two.applyCoarse (a, va2);
    EXPECT_TRUE (va == va2) << "thread count changed the V-cycle";
    const double ab = (va.array () * b.array ()).sum (), ba = (vb.array () * a.array ()).sum ();
    EXPECT_LT (std::abs (ab - ba), 1e-10 * std::sqrt ((va.squaredNorm ()) * b.squaredNorm ()));
    EXPECT_GT ((va.array () * a.array ()).sum (), 0.0);
  }
}

TEST (TikhonovSystem, SolvesEverySignalAsAFreshSystemWouldAndTwiceIsTheSquaredFilter)
{
  // Two spheres far apart (two components: the residual's scale is taken per component)
  // and one point on its own. One system solves f, then its own result, then f again.
  PointMatrix points (2 * 400 + 1, 3);
  points.topRows (400) = toMatrix (synthetic::noisySphere (400, 1.0, 0.02, 71));
  points.middleRows (400, 400) = toMatrix (synthetic::noisySphere (400, 1.0, 0.02, 72));
  points.middleRows (400, 400).col (0).array () += 50.0f;
  points.row (800) << -40.0f, 3.0f, 1.0f;
  const PointGraph g = buildKnnGraph (points);
  const Signal3 f = vertexSignal (g, points);
  const double gamma = 0.4;
  Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig (denseLaplacian (g));
  const Eigen::VectorXd h = (1.0 + 2.0 * gamma * eig.eigenvalues ().array ()).inverse ();
  const Eigen::MatrixXd twice =
      eig.eigenvectors () * h.array ().square ().matrix ().asDiagonal () * eig.eigenvectors ().transpose () * f;
  for (const TikhonovSolver solver : {TikhonovSolver::CONJUGATE_GRADIENT, TikhonovSolver::CHOLMOD})
  {
    TikhonovParams params;
    params.solver = solver;
    params.tolerance = 1e-10;
    const TikhonovSystem system (g, gamma, params);
    SolverReport first, second, again, fresh;
    const Signal3 x1 = system.solve (f, &first);
    const Signal3 x2 = system.solve (x1, &second);
    const Signal3 x3 = system.solve (f, &again);
    // Nothing of a solve stays in the system: the same bits as a fresh system's.
    EXPECT_TRUE ((x3.array () == x1.array ()).all ());
    EXPECT_EQ (again.iterations, first.iterations);
    EXPECT_EQ (again.residual, first.residual);
    const Signal3 y2 = TikhonovSystem (g, gamma, params).solve (x1, &fresh);
    EXPECT_TRUE ((x2.array () == y2.array ()).all ());
    EXPECT_EQ (second.iterations, fresh.iterations);
    EXPECT_EQ (second.residual, fresh.residual);
    EXPECT_TRUE (first.converged && second.converged);
    // Twice is the spectral filter 1 / (1 + 2 gamma lambda)^2.
    EXPECT_LT ((x2 - twice).cwiseAbs ().maxCoeff (), 1e-7) << static_cast<int> (solver);
    EXPECT_EQ (x2.row (static_cast<Eigen::Index> (
                   std::find (g.order.begin (), g.order.end (), VertexIndex (800)) - g.order.begin ())),
               f.row (static_cast<Eigen::Index> (
                   std::find (g.order.begin (), g.order.end (), VertexIndex (800)) - g.order.begin ())));
  }
}

/** A graph of three vertices without edges. */
PointGraph
edgelessGraph ()
{
  PointGraph edgeless;
  edgeless.order = {0, 1, 2};
  edgeless.row_ptr.assign (4, 0);
  return edgeless;
}

/** What TikhonovSystem and TotalVariationSystem share: their settings checked once, at
 *  construction, and each signal at each solve (the system still usable after a rejected
 *  one); gamma 0 the identity, also moved into another system, and the one moved from
 *  refusing to solve; a graph without edges the identity, converged. */
template <typename System, typename Params>
void
expectSystemChecks (const Problem &p, double gamma)
{
  const double nan = std::numeric_limits<double>::quiet_NaN ();
  for (const double bad_gamma : {-1.0, nan, std::numeric_limits<double>::infinity ()})
    EXPECT_THROW (System (p.graph, bad_gamma), std::invalid_argument) << bad_gamma;
  Params bad;
  bad.tolerance = 0.0;
  EXPECT_THROW (System (p.graph, gamma, bad), std::invalid_argument);
  bad = Params{};
  bad.num_threads = -1;
  EXPECT_THROW (System (p.graph, gamma, bad), std::invalid_argument);
  bad = Params{};
  bad.max_iterations = -1;
  EXPECT_THROW (System (p.graph, gamma, bad), std::invalid_argument);
  const System system (p.graph, gamma);
  EXPECT_THROW (system.solve (p.f.topRows (10)), std::invalid_argument);
  Signal3 not_finite = p.f;
  not_finite (3, 1) = nan;
  EXPECT_THROW (system.solve (not_finite), std::invalid_argument);
  SolverReport report;
  EXPECT_FALSE (system.solve (p.f, &report) == p.f);  // still usable after a rejected signal
  EXPECT_TRUE (report.converged);
  System identity (p.graph, 0.0);
  System moved = std::move (identity);
  EXPECT_TRUE (moved.solve (p.f, &report) == p.f);
  EXPECT_TRUE (report.converged);
  EXPECT_EQ (report.iterations, 0);
  EXPECT_THROW (identity.solve (p.f), std::logic_error);  // NOLINT: used after the move on purpose
  const PointGraph edgeless = edgelessGraph ();
  const Signal3 three = p.f.topRows (3);
  EXPECT_TRUE (System (edgeless, 5.0).solve (three, &report) == three);
  EXPECT_TRUE (report.converged);
}

TEST (TikhonovSystem, ChecksItsSettingsOnceAndEachSignal)
{
  const Problem p (200);
  expectSystemChecks<TikhonovSystem, TikhonovParams> (p, 1.0);
  // A graph without edges with CHOLMOD too.
  const PointGraph edgeless = edgelessGraph ();
  const Signal3 three = p.f.topRows (3);
  TikhonovParams params;
  params.solver = TikhonovSolver::CHOLMOD;
  SolverReport report;
  EXPECT_TRUE (TikhonovSystem (edgeless, 5.0, params).solve (three, &report) == three);
  EXPECT_TRUE (report.converged);
}

TEST (TikhonovSystem, ScalesItsStoppingTestPerComponent)
{
  // Two spheres 10^5 apart: with one scale for the whole cloud (the clusters' distance) the
  // stopping test would pass at once; per component each is solved as it is alone.
  const PointMatrix one = toMatrix (synthetic::noisySphere (500, 1.0, 0.02, 81));
  PointMatrix both (1000, 3);
  both.topRows (500) = one;
  both.bottomRows (500) = toMatrix (synthetic::noisySphere (500, 1.0, 0.02, 82));
  both.bottomRows (500).col (0).array () += 1e5f;
  const PointGraph g_one = buildKnnGraph (one), g_both = buildKnnGraph (both);
  TikhonovParams params;
  params.tolerance = 1e-4;
  SolverReport report_one, report_both;
  TikhonovSystem (g_one, 0.5, params).solve (vertexSignal (g_one, one), &report_one);
  TikhonovSystem (g_both, 0.5, params).solve (vertexSignal (g_both, both), &report_both);
  EXPECT_GT (report_one.iterations, 0);
  EXPECT_GE (report_both.iterations, report_one.iterations / 2);
  EXPECT_TRUE (report_both.converged);
  EXPECT_LT (report_both.residual, 1e-4);
}

TEST (Tikhonov, RejectsInvalidInput)
{
  const Problem p (100);
  EXPECT_THROW (solveTikhonov (p.graph, p.f, -1.0), std::invalid_argument);
  EXPECT_THROW (solveTikhonov (p.graph, p.f, std::nan ("")), std::invalid_argument);
  EXPECT_THROW (solveTikhonov (p.graph, Signal3::Zero (5, 3), 1.0), std::invalid_argument);
  TikhonovParams bad;
  bad.tolerance = 0.0;
  EXPECT_THROW (solveTikhonov (p.graph, p.f, 1.0, bad), std::invalid_argument);
  Signal3 nan = p.f;
  nan (3, 0) = std::nan ("");
  EXPECT_THROW (solveTikhonov (p.graph, nan, 1.0), std::invalid_argument);
}

class TotalVariation : public ::testing::TestWithParam<TotalVariationNorm>
{};

TEST_P (TotalVariation, ReachesTheMinimiserOfASecondMethod)
{
  const Problem p (300);
  const double gamma = 0.01;
  TotalVariationParams params;
  params.norm = GetParam ();
  params.tolerance = 1e-7;  // the duals are stored in float: about 1e-8 is the floor
  params.max_iterations = 100000;
  SolverReport report;
  const Signal3 x = solveTotalVariation (p.graph, p.f, gamma, params, &report);
  EXPECT_TRUE (report.converged) << report.residual;
  const Signal3 reference = dualFista (p.graph, p.f, gamma, GetParam (), 40000);
  const double ours = totalVariationObjective (p.graph, p.f, x, gamma, GetParam ());
  const double theirs = totalVariationObjective (p.graph, p.f, reference, gamma, GetParam ());
  EXPECT_LE (std::abs (ours - theirs), 1e-6 * theirs) << ours << " vs " << theirs;
  EXPECT_LT ((x - reference).cwiseAbs ().maxCoeff (), 1e-3);
}

TEST_P (TotalVariation, RowsLongerThanTheSolversBatchReachTheMinimiser)
{
  // k = 70: every row has at least 70 entries, more than the 64 the dual update takes
  // at once, so every row is updated in two or three batches (which also cross row ends).
  const Problem p (120, 0.02, 3, 70);
  for (std::size_t i = 0; i < p.graph.numVertices (); ++i)
    ASSERT_GE (p.graph.row_ptr[i + 1] - p.graph.row_ptr[i], 70u);
  const double gamma = 0.005;
  TotalVariationParams params;
  params.norm = GetParam ();
  params.tolerance = 1e-7;
  params.max_iterations = 100000;
  SolverReport report;
  const Signal3 x = solveTotalVariation (p.graph, p.f, gamma, params, &report);
  EXPECT_TRUE (report.converged) << report.residual;
  const Signal3 reference = dualFista (p.graph, p.f, gamma, GetParam (), 40000);
  const double ours = totalVariationObjective (p.graph, p.f, x, gamma, GetParam ());
  const double theirs = totalVariationObjective (p.graph, p.f, reference, gamma, GetParam ());
  EXPECT_LE (std::abs (ours - theirs), 1e-6 * theirs) << ours << " vs " << theirs;
  EXPECT_LT ((x - reference).cwiseAbs ().maxCoeff (), 1e-3);
}

TEST_P (TotalVariation, NoRandomPerturbationLowersTheObjective)
{
  const Problem p (500);
  const double gamma = 0.02;
  TotalVariationParams params;
  params.norm = GetParam ();
  params.tolerance = 1e-7;
  params.max_iterations = 100000;
  SolverReport report;
  const Signal3 x = solveTotalVariation (p.graph, p.f, gamma, params, &report);
  EXPECT_TRUE (report.converged) << report.residual;
  const double best = totalVariationObjective (p.graph, p.f, x, gamma, GetParam ());
  std::mt19937_64 rng (9);
  std::normal_distribution<double> g;
  for (int trial = 0; trial < 200; ++trial)
  {
    Signal3 delta (x.rows (), 3);
    for (Eigen::Index i = 0; i < delta.rows (); ++i)
      for (int c = 0; c < 3; ++c)
        delta (i, c) = g (rng);
    delta *= 1e-4 / delta.norm () * std::sqrt (double (x.rows ()));
    ASSERT_GE (totalVariationObjective (p.graph, p.f, x + delta, gamma, GetParam ()),
               best * (1.0 - 1e-9));
  }
}

TEST_P (TotalVariation, TheAvx2BuildOfItsLoopsGivesTheSameBits)
{
  // The solver's loops run in an AVX2 build where the processor has it
  // (src/core/wide_kernels.h); the baseline build must give the same result, bit for bit,
  // and so must the objective.
  if (!detail::setWideKernels (true))
    GTEST_SKIP () << "this processor has no AVX2: only the baseline build runs here";
  const Problem p (5000, 0.01);
  TotalVariationParams params;
  params.norm = GetParam ();
  params.tolerance = 1e-4;
  SolverReport wide_report, narrow_report;
  const Signal3 wide = solveTotalVariation (p.graph, p.f, 0.003, params, &wide_report);
  const double wide_objective = totalVariationObjective (p.graph, p.f, wide, 0.003, GetParam ());
  detail::setWideKernels (false);
  const Signal3 narrow = solveTotalVariation (p.graph, p.f, 0.003, params, &narrow_report);
  const double narrow_objective =
      totalVariationObjective (p.graph, p.f, narrow, 0.003, GetParam ());
  detail::setWideKernels (true);
  EXPECT_GT (wide_report.iterations, 10);
  EXPECT_EQ (wide_report.iterations, narrow_report.iterations);
  EXPECT_EQ (wide_report.residual, narrow_report.residual);
  EXPECT_TRUE (wide == narrow);
  EXPECT_EQ (wide_objective, narrow_objective);
  EXPECT_FALSE (wide == p.f);
}

INSTANTIATE_TEST_SUITE_P (Norms, TotalVariation,
                          ::testing::Values (TotalVariationNorm::ISOTROPIC,
                                             TotalVariationNorm::ANISOTROPIC));

TEST (TotalVariationSolver, ZeroGammaIsTheIdentityAndThreadsDoNotMatter)
{
  const Problem p (20000);
  EXPECT_TRUE (solveTotalVariation (p.graph, p.f, 0.0) == p.f);
  TotalVariationParams one, two, three;
  one.num_threads = 1;
  two.num_threads = 2;
  three.num_threads = 3;
  const Signal3 x = solveTotalVariation (p.graph, p.f, 0.01, one);
  EXPECT_TRUE (x == solveTotalVariation (p.graph, p.f, 0.01, two));
  EXPECT_TRUE (x == solveTotalVariation (p.graph, p.f, 0.01, three));
}

TEST (TotalVariationSolver, TheVertexOrderDoesNotMoveTheMinimiser)
{
  // The solver sums each vertex's adjoint over fixed blocks of vertices, and the edges
  // that join two blocks apart: on 10,000 points (three blocks) the same graph with its
  // vertices numbered backwards (other edges join blocks) reaches the same minimiser. An
  // edge between blocks summed wrongly, or not at all, moves it.
  const Problem p (10000);
  const std::size_t n = p.graph.numVertices ();
  PointGraph reversed;
  reversed.order.resize (n);
  reversed.row_ptr.assign (n + 1, 0);
  Signal3 g (p.f.rows (), 3);
  for (std::size_t v = 0; v < n; ++v)
  {
    const std::size_t from = n - 1 - v;
    reversed.order[v] = p.graph.order[from];
    g.row (Eigen::Index (v)) = p.f.row (Eigen::Index (from));
    // Backwards along the row, so that the new row is sorted as a PointGraph's must be.
    for (std::uint64_t e = p.graph.row_ptr[from + 1]; e-- > p.graph.row_ptr[from];)
    {
      reversed.col.push_back (static_cast<VertexIndex> (n - 1 - p.graph.col[e]));
      reversed.weight.push_back (p.graph.weight[e]);
    }
    reversed.row_ptr[v + 1] = reversed.col.size ();
  }
  reversed.sigma = p.graph.sigma;
  reversed.spacing = p.graph.spacing;
  for (std::size_t v = 0; v < n; ++v)
    ASSERT_TRUE (std::is_sorted (reversed.col.begin () + std::ptrdiff_t (reversed.row_ptr[v]),
                                 reversed.col.begin () + std::ptrdiff_t (reversed.row_ptr[v + 1])));
  TotalVariationParams params;
  params.tolerance = 1e-6;
  params.max_iterations = 20000;
  SolverReport forward_report, backward_report;
  const Signal3 forward = solveTotalVariation (p.graph, p.f, 0.01, params, &forward_report);
  const Signal3 backward = solveTotalVariation (reversed, g, 0.01, params, &backward_report);
  ASSERT_TRUE (forward_report.converged && backward_report.converged);
  double largest = 0.0;
  for (std::size_t v = 0; v < n; ++v)
    largest = std::max (largest, (forward.row (Eigen::Index (n - 1 - v)) - backward.row (Eigen::Index (v)))
                                     .cwiseAbs ()
                                     .maxCoeff ());
  EXPECT_LT (largest, 1e-4);  // the points moved by about 1e-2
  EXPECT_GT ((forward - p.f).cwiseAbs ().maxCoeff (), 1e-2);
  const double a = totalVariationObjective (p.graph, p.f, forward, 0.01, TotalVariationNorm::ISOTROPIC);
  const double b = totalVariationObjective (reversed, g, backward, 0.01, TotalVariationNorm::ISOTROPIC);
  EXPECT_LE (std::abs (a - b), 1e-5 * a) << a << " vs " << b;
}

TEST (TotalVariationSolver, ASignalFarFromTheOriginIsSolvedAsWellAsNearIt)
{
  // The dual step's differences are taken in single precision, about a point of the
  // vertex's component: shifting the signal by 10^6 (where a float's step is 0.06, far
  // more than the points' spacing) shifts the minimiser by as much and changes nothing
  // else. (One point far from the rest: SmoothingQuality.AFarPointLeavesTheRestAsItWas.)
  const Problem p (2000, 0.01);
  const Eigen::RowVector3d shift (1e6, -3e5, 2e6);
  TotalVariationParams params;
  params.tolerance = 1e-6;
  SolverReport near_report, far_report;
  const Signal3 near = solveTotalVariation (p.graph, p.f, 0.003, params, &near_report);
  const Signal3 shifted = p.f.rowwise () + shift;
  const Signal3 far = solveTotalVariation (p.graph, shifted, 0.003, params, &far_report);
  EXPECT_TRUE (near_report.converged);
  EXPECT_TRUE (far_report.converged);
  EXPECT_GT (near_report.iterations, 10);
  EXPECT_LT (((far.rowwise () - shift) - near).cwiseAbs ().maxCoeff (), 1e-7);
  EXPECT_GT ((near - p.f).cwiseAbs ().maxCoeff (), 1e-3);  // it did smooth

  // Two spheres 50 apart in one graph (two components), the signal of the one holding
  // vertex 0 shifted by 10^6: each component keeps its own origin, so the other one is
  // solved as before (with one origin for all, its differences would be rounded to 0.06).
  PointMatrix points (1200, 3);
  points.topRows (600) = toMatrix (synthetic::noisySphere (600, 1.0, 0.01, 21));
  points.bottomRows (600) = toMatrix (synthetic::noisySphere (600, 1.0, 0.01, 22));
  points.bottomRows (600).col (1).array () += 50.0f;
  const PointGraph g = buildKnnGraph (points);
  ASSERT_EQ (connectedComponents (g).count, 2u);
  const Signal3 f = vertexSignal (g, points);
  const bool first_low = g.order[0] < 600;  // vertex 0's sphere
  Signal3 moved = f;
  for (Eigen::Index v = 0; v < moved.rows (); ++v)
    if ((g.order[std::size_t (v)] < 600) == first_low)
      moved.row (v) += shift;
  for (const int threads : {1, 2})
  {
    params.num_threads = threads;
    const Signal3 alone = solveTotalVariation (g, f, 0.003, params);
    const Signal3 with_far = solveTotalVariation (g, moved, 0.003, params);
    double other = 0.0;
    for (Eigen::Index v = 0; v < f.rows (); ++v)
      if ((g.order[std::size_t (v)] < 600) != first_low)
        other = std::max (other, (with_far.row (v) - alone.row (v)).cwiseAbs ().maxCoeff ());
    EXPECT_LT (other, 1e-7) << threads << " threads";
    EXPECT_GT ((alone - f).cwiseAbs ().maxCoeff (), 1e-3);
  }
}

TEST (TotalVariationSolver, AHugeGammaStaysWithinTheInputsBoundingBox)
{
  // The minimiser lies within f's bounding box and tends to its mean as gamma grows. The
  // warm start lies about gamma times the degree away from f: at such a gamma the solver
  // starts cold instead, and at its iteration cap it never returns an iterate worse than
  // its start.
  const Problem p (500);
  const Eigen::RowVector3d low = p.f.colwise ().minCoeff (), high = p.f.colwise ().maxCoeff ();
  for (const double gamma : {1e3, 1e5, 1e10})
    for (const int cap : {3, 500})
    {
      TotalVariationParams params;
      params.max_iterations = cap;
      const Signal3 x = solveTotalVariation (p.graph, p.f, gamma, params);
      ASSERT_TRUE (x.allFinite ());
      for (Eigen::Index i = 0; i < x.rows (); ++i)
        for (int c = 0; c < 3; ++c)
        {
          ASSERT_GE (x (i, c), low (c) - 1e-9) << "gamma " << gamma << ", cap " << cap;
          ASSERT_LE (x (i, c), high (c) + 1e-9) << "gamma " << gamma << ", cap " << cap;
        }
      const TotalVariationNorm iso = TotalVariationNorm::ISOTROPIC;
      EXPECT_LE (totalVariationObjective (p.graph, p.f, x, gamma, iso),
                 gamma * totalVariationObjective (p.graph, p.f, p.f, 1.0, iso) * (1.0 + 1e-12))
          << "worse than f itself: gamma " << gamma << ", cap " << cap;
    }
}

TEST (TotalVariationSolver, IterationCapIsReported)
{
  const Problem p (3000);
  TotalVariationParams params;
  params.max_iterations = 3;
  params.tolerance = 1e-12;
  SolverReport report;
  const Signal3 x = solveTotalVariation (p.graph, p.f, 0.05, params, &report);
  EXPECT_FALSE (report.converged);
  EXPECT_EQ (report.iterations, 3);
  EXPECT_GT (report.residual, 0.0);
  EXPECT_TRUE (x.allFinite ());
}

TEST (TotalVariationSolver, StopsWithinAnIterationOfMeetingItsTolerance)
{
  // The first iteration whose gap meets the tolerance, m: a solve capped at m iterations
  // checks the gap there. The solve stops at m or m + 1 once it has the rate of two
  // checks (after 5 and 10 iterations), that is at m + 1 or before when m >= 10 and by
  // iteration 10 when m < 10 (checks at fixed multiples of 10 stopped up to 9 iterations
  // later), with its checks at most 10 iterations apart.
  const Problem p (3000, 0.01);
  const double gamma = defaultTotalVariationGamma (p.graph, 0.01);
  for (const double tolerance : {1e-2, 1e-3, 1e-4})
  {
    TotalVariationParams params;
    params.tolerance = tolerance;
    std::vector<int> checks;
    params.progress = [&] (int iterations, double) { checks.push_back (iterations); };
    SolverReport report;
    solveTotalVariation (p.graph, p.f, gamma, params, &report);
    ASSERT_TRUE (report.converged);
    int previous = 0;
    for (const int check : checks)
    {
      EXPECT_GT (check, previous);
      EXPECT_LE (check - previous, 10);
      previous = check;
    }
    EXPECT_EQ (checks.back (), report.iterations);
    int first = 0;
    for (int cap = 1; cap <= report.iterations && first == 0; ++cap)
    {
      TotalVariationParams capped;
      capped.tolerance = tolerance;
      capped.max_iterations = cap;
      SolverReport at_cap;
      solveTotalVariation (p.graph, p.f, gamma, capped, &at_cap);
      if (at_cap.converged)
        first = at_cap.iterations;
    }
    ASSERT_GT (first, 0) << "tolerance " << tolerance;
    EXPECT_GE (report.iterations, first) << "tolerance " << tolerance;
    EXPECT_LE (report.iterations, std::max (first + 1, 10)) << "tolerance " << tolerance;
  }
}

TEST (TotalVariationSolver, StrongSmoothingConvergesInFewIterations)
{
  // The diagonal preconditioning: at 8 times the rule's strength on a noisy sphere the
  // gap reaches its default tolerance within 80 iterations (the scalar-step accelerated
  // algorithm took 110 on such a sphere), and the result is the minimiser (to the
  // tolerance).
  const Problem p (20000, 0.01);
  const double gamma = 8.0 * defaultTotalVariationGamma (p.graph, 0.01);
  SolverReport report;
  const Signal3 x = solveTotalVariation (p.graph, p.f, gamma, {}, &report);
  EXPECT_TRUE (report.converged);
  EXPECT_LE (report.iterations, 80);
  // A tolerance beyond single precision's reach on the dual step's differences (about
  // 3e-6 here): x-bar is then kept in double, and the gap reaches it (in about 230
  // iterations; in single precision it stalled at 3e-6).
  TotalVariationParams exact;
  exact.tolerance = 1e-6;
  exact.max_iterations = 2000;
  SolverReport exact_report;
  const Signal3 reference = solveTotalVariation (p.graph, p.f, gamma, exact, &exact_report);
  EXPECT_TRUE (exact_report.converged) << exact_report.residual;
  const double ours = totalVariationObjective (p.graph, p.f, x, gamma, TotalVariationNorm::ISOTROPIC);
  const double best =
      totalVariationObjective (p.graph, p.f, reference, gamma, TotalVariationNorm::ISOTROPIC);
  EXPECT_LE (ours - best, 1e-3 * best);
}

TEST (TotalVariationSolver, IsolatedVerticesKeepTheirPositions)
{
  // A vertex without edges (or with only zero weights) has no primal step: it stays put.
  PointGraph graph;
  graph.order = {0, 1, 2, 3, 4};
  graph.row_ptr = {0, 1, 2, 3, 4, 4};
  graph.col = {1, 0, 3, 2};
  graph.weight = {1.0f, 1.0f, 0.0f, 0.0f};
  graph.spacing = 1.0;
  Signal3 f (5, 3);
  f << 0, 0, 0, 1, 0, 0, 5, 5, 5, 7, 7, 7, 9, 9, 9;
  SolverReport report;
  const Signal3 x = solveTotalVariation (graph, f, 0.1, {}, &report);
  EXPECT_TRUE (report.converged);
  for (int v : {2, 3, 4})
    EXPECT_EQ (x.row (v), f.row (v)) << v;
  // The pair moves together by 2 gamma in all: 0.1 each, along the edge.
  EXPECT_NEAR (x (0, 0), 0.1, 1e-4);
  EXPECT_NEAR (x (1, 0), 0.9, 1e-4);
}

TEST (TotalVariationSolver, RejectsInvalidInput)
{
  const Problem p (100);
  EXPECT_THROW (solveTotalVariation (p.graph, p.f, -1.0), std::invalid_argument);
  TotalVariationParams bad;
  bad.max_iterations = -1;
  EXPECT_THROW (solveTotalVariation (p.graph, p.f, 1.0, bad), std::invalid_argument);
  bad = {};
  bad.tolerance = std::nan ("");
  EXPECT_THROW (solveTotalVariation (p.graph, p.f, 1.0, bad), std::invalid_argument);
}

TEST (TotalVariationSystem, SolvesEverySignalAsAFreshSystemWould)
{
  // One system solves f, then its own result (twicing's second solve), then f again: its
  // working arrays stay from one solve to the next, but nothing of a solve may leak into
  // the next. Also at a gamma whose solve starts cold (duals 0) for one signal and warm
  // for the next, in both norms.
  // (At 1e-3 the dual step's differences are taken in single precision, at 1e-5 in double.)
  const Problem p (3000, 0.01);
  for (const TotalVariationNorm norm : {TotalVariationNorm::ISOTROPIC, TotalVariationNorm::ANISOTROPIC})
  for (const double tolerance : {1e-3, 1e-5})
  {
    TotalVariationParams params;
    params.norm = norm;
    params.tolerance = tolerance;
    const TotalVariationSystem system (p.graph, 0.003, params);
    SolverReport first, second, again, fresh;
    const Signal3 x1 = system.solve (p.f, &first);
    const Signal3 x2 = system.solve (x1, &second);
    const Signal3 x3 = system.solve (p.f, &again);
    EXPECT_TRUE (x3 == x1);
    EXPECT_EQ (again.iterations, first.iterations);
    EXPECT_EQ (again.residual, first.residual);
    EXPECT_TRUE (solveTotalVariation (p.graph, x1, 0.003, params, &fresh) == x2);
    EXPECT_EQ (second.iterations, fresh.iterations);
    EXPECT_EQ (second.residual, fresh.residual);
    EXPECT_TRUE (first.converged && second.converged);
    EXPECT_GE (first.iterations, 5);
    EXPECT_FALSE (x2 == x1);

    // gamma 10: the warm start of f lies far off (cold), that of 10^4 f does not. (With
    // no iteration the solve returns its start: f when cold, the warm start else.)
    const Signal3 wide = 1e4 * p.f;
    params.max_iterations = 0;
    TotalVariationSystem start (p.graph, 10.0, params);
    EXPECT_TRUE (start.solve (p.f) == p.f);
    EXPECT_FALSE (start.solve (wide) == wide);
    params.max_iterations = 40;
    TotalVariationSystem strong (p.graph, 10.0, params);
    SolverReport cold, warm, cold_fresh, warm_fresh;
    const Signal3 c1 = strong.solve (p.f, &cold);
    const Signal3 w1 = strong.solve (wide, &warm);
    start = std::move (strong);  // move assignment: the system goes along with its arrays
    const Signal3 c2 = start.solve (p.f, &cold_fresh);
    EXPECT_TRUE (c2 == c1);
    EXPECT_EQ (cold_fresh.residual, cold.residual);
    EXPECT_TRUE (solveTotalVariation (p.graph, wide, 10.0, params, &warm_fresh) == w1);
    EXPECT_EQ (warm_fresh.residual, warm.residual);
  }
}

// The systems keep a reference to their graph: a temporary one does not compile.
static_assert (!std::is_constructible<TikhonovSystem, PointGraph &&, double>::value, "");
static_assert (!std::is_constructible<TikhonovSystem, const PointGraph &&, double>::value, "");
static_assert (std::is_constructible<TikhonovSystem, const PointGraph &, double>::value, "");
static_assert (!std::is_constructible<TotalVariationSystem, PointGraph &&, double>::value, "");
static_assert (!std::is_constructible<TotalVariationSystem, const PointGraph &&, double>::value, "");
static_assert (std::is_constructible<TotalVariationSystem, const PointGraph &, double>::value, "");

TEST (TotalVariationSystem, ChecksItsSettingsOnceAndEachSignal)
{
  const Problem p (200);
  expectSystemChecks<TotalVariationSystem, TotalVariationParams> (p, 0.01);
  // Beyond the largest float the duals cannot hold gamma; without edges nothing is solved.
  EXPECT_THROW (TotalVariationSystem (p.graph, 1e39), std::invalid_argument);
  const PointGraph edgeless = edgelessGraph ();
  const Signal3 three = p.f.topRows (3);
  EXPECT_TRUE (TotalVariationSystem (edgeless, 1e39).solve (three) == three);
  // A graph whose only edge has weight 0: the identity, converged.
  SolverReport report;
  PointGraph weightless;
  weightless.order = {0, 1};
  weightless.row_ptr = {0, 1, 2};
  weightless.col = {1, 0};
  weightless.weight = {0.0f, 0.0f};
  const Signal3 two = p.f.topRows (2);
  EXPECT_TRUE (TotalVariationSystem (weightless, 5.0).solve (two, &report) == two);
  EXPECT_TRUE (report.converged);
}

/** estimateNoise on the default k-NN graph of a cloud. */
NoiseEstimate
noiseOf (const PointMatrix &points, int num_threads = 0)
{
  const PointGraph g = buildKnnGraph (points);
  return estimateNoise (g, vertexSignal (g, points), num_threads);
}

TEST (NoiseLevel, RecoversTheNoiseAndTheSpacingOfSmoothSurfaces)
{
  // From a tenth of the spacing to 2.5 spacings, where the neighbours of a point come
  // from inside the noise and the plane fit's residual alone falls to 0.7 of it.
  const double plane_spacing = 2.0 / std::sqrt (20000.0);  // 20,000 points on a 2 x 2 square
  const double sphere_spacing = std::sqrt (4.0 * M_PI / 50000.0);
  for (double noise : {0.002, 0.005, 0.01, 0.02, 0.04})
  {
    const NoiseEstimate p = noiseOf (toMatrix (synthetic::noisyPlane (20000, noise, 4)));
    EXPECT_NEAR (p.level, noise, 0.1 * noise) << "plane, noise " << noise;
    EXPECT_NEAR (p.spacing, plane_spacing, 0.05 * plane_spacing) << "plane, noise " << noise;
    const NoiseEstimate s = noiseOf (toMatrix (synthetic::noisySphere (50000, 1.0, noise, 5)));
    EXPECT_NEAR (s.level, noise, 0.1 * noise) << "sphere, noise " << noise;
    EXPECT_NEAR (s.spacing, sphere_spacing, 0.05 * sphere_spacing) << "sphere, noise " << noise;
    if (noise == 0.04)  // 2.5 spacings: the residual alone is far short
      EXPECT_LT (s.two_ring, 0.8 * noise);
  }
  // Scale invariance: the same cloud in millimetres; and thread-count independence.
  const PointMatrix m = toMatrix (synthetic::noisySphere (20000, 1.0, 0.01, 6));
  const NoiseEstimate a = noiseOf (m), b = noiseOf (1000.0f * m);
  EXPECT_NEAR (b.level, 1000.0 * a.level, 1e-3 * b.level);
  EXPECT_NEAR (b.spacing, 1000.0 * a.spacing, 1e-3 * b.spacing);
  const NoiseEstimate one = noiseOf (m, 1), two = noiseOf (m, 2);
  EXPECT_EQ (one.level, two.level);
  EXPECT_EQ (one.spacing, two.spacing);
  // No edges, or all points on one spot: no estimate, no crash; sizes must agree.
  EXPECT_EQ (noiseOf (PointMatrix::Zero (1, 3)).level, 0.0);
  EXPECT_EQ (noiseOf (PointMatrix::Zero (3, 3)).level, 0.0);
  const NoiseEstimate spot = noiseOf (PointMatrix::Ones (100, 3));
  EXPECT_EQ (spot.level, 0.0);
  EXPECT_EQ (spot.spacing, 0.0);
  const PointGraph g = buildKnnGraph (m);
  EXPECT_THROW (estimateNoise (g, Signal3::Zero (10, 3)), std::invalid_argument);
}

TEST (NoiseLevel, RecoversNoiseOfSeveralSpacings)
{
  // Noise of 6 and 8 spacings: the ball that counts the points for the spacing is widened
  // while the level exceeds 0.45 of its radius. With the ball of 4 mean 10-NN distances
  // alone the noise read 22% high at 6 spacings here (18% on the 160,000-point planes of
  // the table) and was pinned at the table's last row, 8 spacings, beyond. (On this small
  // plane the wider ball meets the edges and reads the spacing up to 11% long: 0.95 and
  // 0.92 of the noise.)
  const double spacing = 2.0 / std::sqrt (20000.0);  // 20,000 points on a 2 x 2 square
  for (double ratio : {6.0, 8.0})
  {
    const double noise = ratio * spacing;
    const NoiseEstimate p = noiseOf (toMatrix (synthetic::noisyPlane (20000, noise, 12)));
    EXPECT_NEAR (p.level, noise, 0.1 * noise) << "plane, " << ratio << " spacings";
    EXPECT_NEAR (p.spacing, spacing, 0.12 * spacing) << "plane, " << ratio << " spacings";
  }
}

TEST (NoiseLevel, MeasuresHowTheSurfaceBends)
{
  // A sphere of radius r reads 1 / (4 sqrt(3) r) (heights a^2 / 2r over a uniform disc),
  // whatever the noise and the density; a plane only the scatter of its noise.
  for (double radius : {0.5, 2.0})
    for (std::size_t n : {10000ul, 50000ul})
    {
      const NoiseEstimate s = noiseOf (toMatrix (synthetic::noisySphere (n, radius, 0.005 * radius, 8)));
      const double expected = 1.0 / (4.0 * std::sqrt (3.0) * radius);
      EXPECT_NEAR (s.curvature, expected, 0.15 * expected) << "sphere r " << radius << ", " << n;
    }
  const double sphere = noiseOf (toMatrix (synthetic::noisySphere (20000, 1.0, 0.01, 9))).curvature;
  const NoiseEstimate plane = noiseOf (toMatrix (synthetic::noisyPlane (20000, 0.01, 9)));
  EXPECT_GT (plane.curvature, 0.0);
  EXPECT_LT (plane.curvature, 0.5 * sphere);
  // Detail a few spacings wide bends far more than the sphere.
  PointMatrix bumps = toMatrix (synthetic::noisyPlane (20000, 0.002, 10));
  for (Eigen::Index i = 0; i < bumps.rows (); ++i)
    bumps (i, 2) += 0.03f * std::sin (40.0f * bumps (i, 0)) * std::sin (40.0f * bumps (i, 1));
  EXPECT_GT (noiseOf (bumps).curvature, 4.0 * sphere);
  // In 1 / the points' unit, and independent of the threads.
  const PointMatrix m = toMatrix (synthetic::noisySphere (20000, 1.0, 0.01, 6));
  EXPECT_NEAR (noiseOf (1000.0f * m).curvature, noiseOf (m).curvature / 1000.0, 1e-3 * noiseOf (m).curvature / 1000.0);
  EXPECT_EQ (noiseOf (m, 1).curvature, noiseOf (m, 2).curvature);
  // Noise of several spacings buries the bending of a dense sphere: every ball is as
  // thick as the noise, read as no bending (0), not as "not measured".
  EXPECT_EQ (noiseOf (toMatrix (synthetic::noisySphere (50000, 1.0, 0.08, 11))).curvature, 0.0);
  // Not measured without edges or on one spot.
  EXPECT_EQ (noiseOf (PointMatrix::Zero (3, 3)).curvature, -1.0);
  EXPECT_EQ (noiseOf (PointMatrix::Ones (100, 3)).curvature, -1.0);
  EXPECT_EQ (NoiseEstimate{}.curvature, -1.0);
}

TEST (DefaultGamma, DetailFactorFollowsTheDetailLengthInSpacings)
{
  const PointMatrix m = toMatrix (synthetic::noisySphere (20000, 1.0, 0.01, 6));
  const PointGraph a = buildKnnGraph (m), b = buildKnnGraph (1000.0f * m);
  const double h = a.spacing;
  // Detail length 1 / curvature: 40 spacings give Tikhonov 1, 30 give TV 1.
  EXPECT_NEAR (detailGammaFactor (a, 1.0 / (40.0 * h), SmoothingKind::TIKHONOV), 1.0, 1e-12);
  EXPECT_NEAR (detailGammaFactor (a, 1.0 / (30.0 * h), SmoothingKind::TOTAL_VARIATION), 1.0, 1e-12);
  EXPECT_NEAR (detailGammaFactor (a, 1.0 / (160.0 * h), SmoothingKind::TIKHONOV), 4.0, 1e-12);
  EXPECT_NEAR (detailGammaFactor (a, 1.0 / (20.0 * h), SmoothingKind::TIKHONOV_CHOLMOD), 0.5, 1e-12);
  // Unit invariant: the same curvature in 1 / millimetres.
  EXPECT_NEAR (detailGammaFactor (b, 1.0 / (160.0 * h) / 1000.0, SmoothingKind::TIKHONOV), 4.0, 1e-4);
  // Held within [1/8, 16]: 16 too for no bending (0: an unbounded detail length, as the
  // limit of a bending that falls to 0); 1 when not measured (negative) or unusable.
  EXPECT_EQ (detailGammaFactor (a, 1e-9 / h, SmoothingKind::TIKHONOV), 16.0);
  EXPECT_EQ (detailGammaFactor (a, 1e3 / h, SmoothingKind::TOTAL_VARIATION), 0.125);
  EXPECT_EQ (detailGammaFactor (a, 0.0, SmoothingKind::TIKHONOV), 16.0);
  EXPECT_EQ (detailGammaFactor (a, 0.0, SmoothingKind::TOTAL_VARIATION), 16.0);
  for (double bad : {-1.0, -1e-300, std::nan (""), std::numeric_limits<double>::infinity ()})
    EXPECT_EQ (detailGammaFactor (a, bad, SmoothingKind::TIKHONOV), 1.0) << bad;
  EXPECT_EQ (detailGammaFactor (PointGraph{}, 1.0, SmoothingKind::TIKHONOV), 1.0);
}

TEST (DefaultGamma, NoiseFactorFollowsTheNoiseToSpacingRatioForTotalVariationOnly)
{
  const PointMatrix m = toMatrix (synthetic::noisySphere (20000, 1.0, 0.01, 6));
  const PointGraph a = buildKnnGraph (m), b = buildKnnGraph (1000.0f * m);
  const double h = a.spacing;
  const auto tv = SmoothingKind::TOTAL_VARIATION;
  // (r / 0.5)^1.5 with r = noise / spacing.
  EXPECT_NEAR (noiseGammaFactor (a, 0.5 * h, tv), 1.0, 1e-12);
  EXPECT_NEAR (noiseGammaFactor (a, 0.8 * h, tv), std::pow (1.6, 1.5), 1e-12);
  EXPECT_NEAR (noiseGammaFactor (a, 0.4 * h, tv), std::pow (0.8, 1.5), 1e-12);
  // Unit invariant.
  EXPECT_NEAR (noiseGammaFactor (b, 800.0 * h, tv), std::pow (1.6, 1.5), 1e-4);
  // Held within [1/2, 3].
  EXPECT_EQ (noiseGammaFactor (a, 0.01 * h, tv), 0.5);
  EXPECT_EQ (noiseGammaFactor (a, 10.0 * h, tv), 3.0);
  // Tikhonov's rule already carries the ratio; 1 when the noise is unusable.
  EXPECT_EQ (noiseGammaFactor (a, 0.8 * h, SmoothingKind::TIKHONOV), 1.0);
  EXPECT_EQ (noiseGammaFactor (a, 0.8 * h, SmoothingKind::TIKHONOV_CHOLMOD), 1.0);
  for (double bad : {0.0, -1.0, std::nan (""), std::numeric_limits<double>::infinity ()})
    EXPECT_EQ (noiseGammaFactor (a, bad, tv), 1.0) << bad;
  EXPECT_EQ (noiseGammaFactor (PointGraph{}, 0.01, tv), 1.0);
}

TEST (DefaultGamma, HighNoiseFactorScalesTheRulesBeyondFourSpacingsOfNoise)
{
  const auto tv = SmoothingKind::TOTAL_VARIATION;
  // r = noise / surface spacing: 1 up to 4, then r / 4 for TV and 4 / r for Tikhonov.
  EXPECT_EQ (highNoiseGammaFactor (0.3, 0.1, tv), 1.0);
  EXPECT_EQ (highNoiseGammaFactor (0.4, 0.1, SmoothingKind::TIKHONOV), 1.0);
  EXPECT_NEAR (highNoiseGammaFactor (0.8, 0.1, tv), 2.0, 1e-12);
  EXPECT_NEAR (highNoiseGammaFactor (0.8, 0.1, SmoothingKind::TIKHONOV), 0.5, 1e-12);
  EXPECT_NEAR (highNoiseGammaFactor (0.6, 0.1, SmoothingKind::TIKHONOV_CHOLMOD), 4.0 / 6.0, 1e-12);
  // Unit invariant; 1 when either length is unusable.
  EXPECT_NEAR (highNoiseGammaFactor (800.0, 100.0, tv), 2.0, 1e-12);
  for (double bad : {0.0, -1.0, std::nan (""), std::numeric_limits<double>::infinity ()})
  {
    EXPECT_EQ (highNoiseGammaFactor (bad, 0.1, tv), 1.0) << bad;
    EXPECT_EQ (highNoiseGammaFactor (0.8, bad, tv), 1.0) << bad;
  }
}

TEST (DefaultGamma, DensityNormalizationFadesOutUnderNoiseOfSeveralSpacings)
{
  EXPECT_EQ (densityNormalizationPower (0.01, 0.02), 1.0);
  EXPECT_EQ (densityNormalizationPower (2.5, 1.0), 1.0);
  EXPECT_NEAR (densityNormalizationPower (3.0, 1.0), 0.5, 1e-12);
  EXPECT_NEAR (densityNormalizationPower (0.3, 0.1), 0.5, 1e-12);  // unit-free
  EXPECT_EQ (densityNormalizationPower (3.5, 1.0), 0.0);
  EXPECT_EQ (densityNormalizationPower (8.0, 1.0), 0.0);
  // Not measured: full.
  for (const double bad : {0.0, -1.0, std::numeric_limits<double>::infinity (),
                           std::numeric_limits<double>::quiet_NaN ()})
  {
    EXPECT_EQ (densityNormalizationPower (bad, 1.0), 1.0) << bad;
    EXPECT_EQ (densityNormalizationPower (1.0, bad), 1.0) << bad;
  }
}

TEST (DefaultGamma, RefinedFactorIsTheProductOfTheTermsHeldWithinTheDetailBounds)
{
  const PointMatrix m = toMatrix (synthetic::noisySphere (20000, 1.0, 0.01, 6));
  const PointGraph a = buildKnnGraph (m);
  const double h = a.spacing;
  const auto tv = SmoothingKind::TOTAL_VARIATION, tikhonov = SmoothingKind::TIKHONOV;
  // Detail 2 (60 spacings) and noise 1.6^1.5 for TV; Tikhonov has no noise term.
  EXPECT_NEAR (refinedGammaFactor (a, 0.8 * h, 1.0 / (60.0 * h), tv), 2.0 * std::pow (1.6, 1.5), 1e-12);
  EXPECT_NEAR (refinedGammaFactor (a, 0.8 * h, 1.0 / (80.0 * h), tikhonov), 2.0, 1e-12);
  // Detail 16 (its bound) times noise 3 is held at 16; detail 1/8 times noise 1/2 at 1/8.
  EXPECT_EQ (refinedGammaFactor (a, 10.0 * h, 1e-9 / h, tv), 16.0);
  EXPECT_EQ (refinedGammaFactor (a, 0.01 * h, 1e3 / h, tv), 0.125);
  // Detail 8 times noise 1.6^1.5 = 16.2: held too.
  EXPECT_EQ (refinedGammaFactor (a, 0.8 * h, 1.0 / (240.0 * h), tv), 16.0);
}

TEST (DefaultGamma, IsUnitInvariantAndGrowsWithNoise)
{
  const PointMatrix m = toMatrix (synthetic::noisySphere (20000, 1.0, 0.01, 6));
  const PointMatrix mm = m * 1000.0f;
  const PointGraph a = buildKnnGraph (m), b = buildKnnGraph (mm);
  EXPECT_NEAR (defaultTikhonovGamma (a, 0.01), defaultTikhonovGamma (b, 10.0),
               1e-4 * defaultTikhonovGamma (a, 0.01));
  EXPECT_NEAR (1000.0 * defaultTotalVariationGamma (a, 0.01), defaultTotalVariationGamma (b, 10.0),
               1e-3 * defaultTotalVariationGamma (b, 10.0));
  EXPECT_GT (defaultTikhonovGamma (a, 0.02), defaultTikhonovGamma (a, 0.01));
  EXPECT_GT (defaultTotalVariationGamma (a, 0.02), defaultTotalVariationGamma (a, 0.01));
  EXPECT_EQ (defaultTikhonovGamma (a, 0.0), 0.0);
}

// ---- The strength chosen by Stein's unbiased risk estimate ---------------------------

namespace {

/** Plain Tikhonov as a Denoiser (linear: the risk estimate is then exact in expectation). */
Signal3
tikhonovDenoiser (const PointGraph &g, const Signal3 &f, double gamma)
{
  return solveTikhonov (g, f, gamma);
}

/** Mean squared distance of the vertices to the unit sphere. */
double
sphereError (const Signal3 &x)
{
  double sum = 0.0;
  for (Eigen::Index v = 0; v < x.rows (); ++v)
    sum += std::pow (x.row (v).norm () - 1.0, 2);
  return sum / double (x.rows ());
}

} // namespace

TEST (RiskSelection, LandsNearTheTrueBestOfTheMultiples)
{
  for (double noise : {0.005, 0.02})
  {
    const PointMatrix sphere = toMatrix (synthetic::noisySphere (10000, 1.0, noise, 61));
    const PointGraph g = buildKnnGraph (sphere);
    const Signal3 f = vertexSignal (g, sphere);
    const double gamma = defaultTikhonovGamma (g, noise);
    RiskSelectionParams params;
    const double chosen = selectGammaByRisk (g, f, noise, gamma, tikhonovDenoiser, params);
    double best = std::numeric_limits<double>::infinity (), best_m = 0.0, worst = 0.0;
    for (double m : params.multiples)
    {
      const double e = sphereError (tikhonovDenoiser (g, f, m * gamma));
      if (e < best)
        best = e, best_m = m;
      worst = std::max (worst, e);
    }
    ASSERT_GT (worst, 2.0 * best);  // the choice matters: a wrong one would fail below
    const double e = sphereError (tikhonovDenoiser (g, f, chosen));
    std::printf ("noise %g: chosen %.3g x the rule (error %.4g), best of the multiples %g x (%.4g)\n",
                 noise, chosen / gamma, e, best_m, best);
    EXPECT_LT (e, 1.1 * best) << noise;
    // Deterministic, and unchanged by the unit of the cloud.
    EXPECT_EQ (selectGammaByRisk (g, f, noise, gamma, tikhonovDenoiser, params), chosen);
    const PointMatrix mm = sphere * 1000.0f;
    const PointGraph h = buildKnnGraph (mm);
    EXPECT_NEAR (selectGammaByRisk (h, vertexSignal (h, mm), 1000.0 * noise,
                                    defaultTikhonovGamma (h, 1000.0 * noise), tikhonovDenoiser, params) /
                     defaultTikhonovGamma (h, 1000.0 * noise),
                 chosen / gamma, 1e-6);
  }
}

TEST (RiskSelection, BlocksOfALargeGraphChooseLikeTheWholeGraph)
{
  const double noise = 0.01;
  const PointMatrix sphere = toMatrix (synthetic::noisySphere (40000, 1.0, noise, 62));
  const PointGraph g = buildKnnGraph (sphere);
  const Signal3 f = vertexSignal (g, sphere);
  const double gamma = defaultTikhonovGamma (g, noise);
  std::size_t largest = 0;
  RiskSelectionParams whole, blocks;
  blocks.sample_size = 12000;  // four blocks of 3,000 consecutive vertices
  const auto counting = [&] (const PointGraph &graph, const Signal3 &s, double gm) {
    largest = std::max (largest, graph.numVertices ());
    return tikhonovDenoiser (graph, s, gm);
  };
  const double all = selectGammaByRisk (g, f, noise, gamma, counting, whole);
  EXPECT_EQ (largest, g.numVertices ());
  largest = 0;
  const double sampled = selectGammaByRisk (g, f, noise, gamma, counting, blocks);
  EXPECT_EQ (largest, 3000u);
  std::printf ("whole graph %.3g x the rule, four blocks %.3g x\n", all / gamma, sampled / gamma);
  EXPECT_LE (std::abs (std::log2 (sampled / all)), 0.51);  // at most one step of sqrt 2
}

TEST (RiskSelection, DegenerateInputsKeepGammaAndInvalidSettingsThrow)
{
  const PointMatrix sphere = toMatrix (synthetic::noisySphere (500, 1.0, 0.01, 63));
  const PointGraph g = buildKnnGraph (sphere);
  const Signal3 f = vertexSignal (g, sphere);
  int calls = 0;
  const Denoiser counting = [&] (const PointGraph &graph, const Signal3 &s, double gm) {
    ++calls;
    return tikhonovDenoiser (graph, s, gm);
  };
  EXPECT_EQ (selectGammaByRisk (g, f, 0.0, 0.5, counting), 0.5);  // no noise
  EXPECT_EQ (selectGammaByRisk (g, f, 0.01, 0.0, counting), 0.0);  // no smoothing
  EXPECT_EQ (selectGammaByRisk (g, f, std::nan (""), 0.5, counting), 0.5);
  const PointGraph single = buildKnnGraph (PointMatrix::Zero (1, 3));
  EXPECT_EQ (selectGammaByRisk (single, Signal3::Zero (1, 3), 0.01, 0.5, counting), 0.5);  // no edges
  EXPECT_EQ (calls, 0);
  EXPECT_THROW (selectGammaByRisk (g, Signal3::Zero (3, 3), 0.01, 0.5, counting), std::invalid_argument);
  EXPECT_THROW (selectGammaByRisk (g, f, 0.01, 0.5, Denoiser ()), std::invalid_argument);
  RiskSelectionParams bad;
  bad.multiples = {};
  EXPECT_THROW (selectGammaByRisk (g, f, 0.01, 0.5, counting, bad), std::invalid_argument);
  bad.multiples = {1.0, -2.0};
  EXPECT_THROW (selectGammaByRisk (g, f, 0.01, 0.5, counting, bad), std::invalid_argument);
  bad.multiples = {1.0};
  bad.sample_size = 0;
  EXPECT_THROW (selectGammaByRisk (g, f, 0.01, 0.5, counting, bad), std::invalid_argument);
  bad.sample_size = 100;
  bad.num_threads = -1;
  EXPECT_THROW (selectGammaByRisk (g, f, 0.01, 0.5, counting, bad), std::invalid_argument);
  // A run that overflows is never chosen, wherever it comes in the order tried.
  const Denoiser overflowing = [&] (const PointGraph &graph, const Signal3 &s, double gm) {
    Signal3 x = tikhonovDenoiser (graph, s, gm);
    if (gm < 0.3 * 0.5)
      x (0, 0) = std::numeric_limits<double>::quiet_NaN ();
    return x;
  };
  EXPECT_GE (selectGammaByRisk (g, f, 0.01, 0.5, overflowing), 0.3 * 0.5);
  // A single multiple: it and its two neighbours are tried (2 runs each), the run at the
  // given gamma being the one the normals came from.
  RiskSelectionParams one;
  one.multiples = {1.0};
  calls = 0;
  const double chosen = selectGammaByRisk (g, f, 0.01, 0.5, counting, one);
  EXPECT_EQ (calls, 1 + 1 + 2 * 2);
  EXPECT_TRUE (chosen == 0.5 || std::abs (chosen / 0.5 - std::sqrt (2.0)) < 1e-9 ||
               std::abs (chosen / 0.5 - 1.0 / std::sqrt (2.0)) < 1e-9);
}

/*
 * pcl_graph_denoise: graph-signal-processing point cloud denoising for PCL.
 * SPDX-License-Identifier: BSD-3-Clause
 */
#pragma once

/** \file solvers.h
 *  \brief The paper's two position denoisers on a PointGraph, for N x 3 signals:
 *
 *  - Tikhonov: x = argmin 1/2 |x - f|^2 + gamma x^T L x, i.e. (I + 2 gamma L) x = f
 *    (spectral filter 1 / (1 + 2 gamma lambda), GSPBox's convention);
 *  - total variation: x = argmin 1/2 |x - f|^2 + gamma sum_e |(grad x)_e|, with
 *    (grad x)_e = sqrt(w_ij) (x_i - x_j) over each edge once; isotropic (the Euclidean
 *    norm of the 3-vector difference, rotation invariant) or anisotropic (the sum of
 *    the three absolute differences).
 *
 *  Signals are in the graph's internal vertex order. Solvers never throw on
 *  non-convergence: they return their best iterate and say so in the report.
 */

#include <pcl_graph_denoise/core/graph.h>
#include <pcl_graph_denoise/core/memory.h>

#include <functional>
#include <memory>
#include <string>
#include <vector>

namespace pcl_graph_denoise {
namespace core {

/** \brief What a solver did. */
struct SolverReport
{
  int iterations = 0;       ///< iterations run
  double residual = 0.0;    ///< final stopping measure (see each solver)
  bool converged = false;   ///< the stopping measure reached the tolerance
};

/** \brief Solvers for the Tikhonov system (I + 2 gamma L) x = f. */
enum class TikhonovSolver
{
  /** Preconditioned CG, three columns fused (default): Jacobi plus a V-cycle on coarse
   *  graphs of aggregated consecutive (spatially ordered) vertices, which about halves
   *  the iterations of Jacobi alone at the filters' strengths. In mixed precision: its
   *  vectors in single precision first (the loop is bound by memory traffic), then the
   *  residual of the result recomputed in double and, where it is still above the
   *  tolerance, CG in double precision from there. The reported residual is the one of
   *  the returned x, in double. */
  CONJUGATE_GRADIENT,
  CHOLMOD              ///< exact sparse Cholesky (SuiteSparse); for small and medium clouds
};

/** \brief Settings of solveTikhonov. */
struct TikhonovParams
{
  /** Which solver; default TikhonovSolver::CONJUGATE_GRADIENT. */
  TikhonovSolver solver = TikhonovSolver::CONJUGATE_GRADIENT;
  /** CG stops when |r| <= tolerance |f - mean(f)| (Frobenius norms over the three
   *  columns; the mean of each connected component of the graph, which the solve leaves
   *  unchanged, does not count, so that clusters far apart do not loosen it; nor can a
   *  few far points: the scale is at most 4 sqrt(N) times the median distance of the
   *  points from their per-axis median, which a compact cloud never reaches). Since
   *  I + 2 gamma L >= I, the solution's error is at most the residual: 1e-5 of the
   *  cloud's extent, far below any noise worth removing. */
  double tolerance = 1e-5;
  int max_iterations = 1000;  ///< CG iteration cap; valid >= 0 (0 returns f unsolved)
  int num_threads = 0;        ///< 0 = all hardware threads; valid >= 0
  /** Called every 10 CG iterations with the iterations done and the relative residual
   *  then, from the calling thread; empty (default) = silent. For progress reports. */
  std::function<void (int iterations, double residual)> progress;
};

/** \brief Solves (I + 2 gamma L) x = f for the three columns of f.
 *  \throws std::invalid_argument on invalid parameters or sizes.
 *  \throws std::runtime_error when gamma is too large for double precision: the result
 *  overflowed, or lies outside the bounding box of f by more than the box's size (the
 *  exact solution lies inside it; on a unit sphere from gamma about 1e20). */
Signal3
solveTikhonov (const PointGraph &graph, const Signal3 &f, double gamma,
               const TikhonovParams &params = {}, SolverReport *report = nullptr);

/** \brief The system I + 2 gamma L of one graph and strength, set up once and solved for
 *  any number of right-hand sides (a precompute / solve split): the graph's connected
 *  components (for the stopping test's scale) and the weighted degrees and coarse levels of
 *  the conjugate gradient, or CHOLMOD's factorisation, come with the constructor. Twicing (the filters' shrinkage correction)
 *  solves the same system twice; solveTikhonov is one system solved once, and each solve
 *  here gives the same result as solveTikhonov with the same settings, bit for bit. The
 *  graph must outlive the system; solve() is not for concurrent calls on one system. */
class TikhonovSystem
{
public:
  /** \throws std::invalid_argument on invalid parameters or gamma.
   *  \throws std::runtime_error when CHOLMOD cannot factorise the system (see
   *  solveTikhonov). */
  TikhonovSystem (const PointGraph &graph, double gamma, const TikhonovParams &params = {});
  /** \brief Not from a temporary graph: the system keeps a reference to it. */
  TikhonovSystem (PointGraph &&graph, double gamma, const TikhonovParams &params = {}) = delete;
  /** \brief Not from a temporary graph: the system keeps a reference to it. */
  TikhonovSystem (const PointGraph &&graph, double gamma, const TikhonovParams &params = {}) = delete;
  ~TikhonovSystem ();
  /** \brief Takes over another system (which may then only be destroyed or assigned). */
  TikhonovSystem (TikhonovSystem &&) noexcept;
  /** \brief Takes over another system (which may then only be destroyed or assigned). */
  TikhonovSystem &
  operator= (TikhonovSystem &&) noexcept;

  /** \brief Solves (I + 2 gamma L) x = f for the three columns of f (as solveTikhonov).
   *  \throws std::invalid_argument when f has the wrong size or is not finite.
   *  \throws std::logic_error on a system moved from.
   *  \throws std::runtime_error as solveTikhonov. */
  Signal3
  solve (const Signal3 &f, SolverReport *report = nullptr) const;

private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

/** \brief Which norm of the edge differences total variation penalises. */
enum class TotalVariationNorm
{
  ISOTROPIC,   ///< Euclidean norm of each edge's 3-vector difference (default)
  ANISOTROPIC  ///< sum of the absolute differences of x, y and z
};

/** \brief Settings of solveTotalVariation. */
struct TotalVariationParams
{
  /** Which norm of the edge differences; default TotalVariationNorm::ISOTROPIC. */
  TotalVariationNorm norm = TotalVariationNorm::ISOTROPIC;
  /** Stops when the primal-dual gap is at most tolerance x the primal objective (checked
   *  after 5 and 10 iterations, then at most 10 apart, when its rate of fall since the
   *  last check would bring it to the tolerance: the stop comes within about an iteration
   *  of meeting it). With the solver's warm start, 1e-3 lands within about 1% of
   *  the exact minimiser's distance to the surface on noisy spheres. The dual step's
   *  differences are taken in single precision unless the tolerance is below ten times
   *  their rounding (2^-24 times the cloud's extent over its mean edge length); the duals
   *  are single precision, which puts the floor near 1e-8. */
  double tolerance = 1e-3;
  /** Iteration cap; valid >= 0. 0 returns the start: f - grad^T y with every dual at
   *  gamma along its edge's difference of f (or f itself where that start's objective is
   *  over 100 times f's). */
  int max_iterations = 500;
  int num_threads = 0;       ///< 0 = all hardware threads; valid >= 0
  /** Called at every duality-gap check (see tolerance; and at the cap) with the
   *  iterations done and the relative gap then, from the calling thread; empty (default)
   *  = silent. For progress reports. */
  std::function<void (int iterations, double residual)> progress;
};

/** \brief Total-variation denoising by the primal-dual algorithm of Chambolle and Pock,
 *  which needs no inner linear solve: diagonally preconditioned (Pock and Chambolle 2011:
 *  a step per vertex, 1 / sum_j sqrt(w_ij), and per edge) and accelerated by a global
 *  scale of the steps as in their algorithm 2 (the data term is 1-strongly convex),
 *  warm-started with every edge's dual on the boundary of its ball along the edge's
 *  difference. The reported residual is the relative
 *  duality gap.
 *  \throws std::invalid_argument on invalid parameters or sizes.
 *  \throws std::runtime_error when gamma is too large for double precision: the result
 *  overflowed, or lies outside the bounding box of f by more than the box's size (the
 *  exact minimiser lies inside it). */
Signal3
solveTotalVariation (const PointGraph &graph, const Signal3 &f, double gamma,
                     const TotalVariationParams &params = {}, SolverReport *report = nullptr);

/** \brief The total-variation problem of one graph and strength, set up once and solved for
 *  any number of signals (as TikhonovSystem): the undirected edges, each once, with their
 *  sqrt(w) (8 bytes per edge, half the stored entries), the vertices' steps and the graph's
 *  components come with the constructor, and the solver's working arrays (the duals, 12
 *  bytes per edge, and 36 bytes per vertex, 48 where a tolerance needs the dual step's
 *  differences in double) are allocated by the first solve and kept for the system's
 *  lifetime instead of being allocated and faulted in again. Twicing (the filters' shrinkage correction) solves the same problem twice;
 *  solveTotalVariation is one system solved once, and each solve here gives the same result
 *  as solveTotalVariation with the same settings, bit for bit. The graph must outlive the
 *  system; solve() is not for concurrent calls on one system (it writes those arrays). */
class TotalVariationSystem
{
public:
  /** \throws std::invalid_argument on invalid parameters or gamma (also a gamma above the
   *  largest float where the graph has entries: the duals are single precision). */
  TotalVariationSystem (const PointGraph &graph, double gamma,
                        const TotalVariationParams &params = {});
  /** \brief Not from a temporary graph: the system keeps a reference to it. */
  TotalVariationSystem (PointGraph &&graph, double gamma,
                        const TotalVariationParams &params = {}) = delete;
  /** \brief Not from a temporary graph: the system keeps a reference to it. */
  TotalVariationSystem (const PointGraph &&graph, double gamma,
                        const TotalVariationParams &params = {}) = delete;
  ~TotalVariationSystem ();
  /** \brief Takes over another system (which may then only be destroyed or assigned). */
  TotalVariationSystem (TotalVariationSystem &&) noexcept;
  /** \brief Takes over another system (which may then only be destroyed or assigned). */
  TotalVariationSystem &
  operator= (TotalVariationSystem &&) noexcept;

  /** \brief The minimiser of 1/2 |x - f|^2 + gamma TV(x) (as solveTotalVariation).
   *  \throws std::invalid_argument when f has the wrong size or is not finite.
   *  \throws std::logic_error on a system moved from.
   *  \throws std::runtime_error as solveTotalVariation. */
  Signal3
  solve (const Signal3 &f, SolverReport *report = nullptr) const;

private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

/** \brief The total-variation objective 1/2 |x - f|^2 + gamma TV(x). */
double
totalVariationObjective (const PointGraph &graph, const Signal3 &f, const Signal3 &x,
                         double gamma, TotalVariationNorm norm);

/** \brief The data-derived Tikhonov strength for a graph and a noise level (in the
 *  points' units): gamma = 20 (noise / spacing)^1.5 / mean weighted degree. The best
 *  gamma grows with the noise and with the density (gamma x mean degree from about 10
 *  at 100k points to 100 at 1M points on a noisy sphere); the noise-to-spacing ratio
 *  carries both. Calibrated for the paper's filters on noisy spheres and cubes. Unitless;
 *  0 when the graph has no edges or the noise is 0. */
double
defaultTikhonovGamma (const PointGraph &graph, double noise);

/** \brief The data-derived total-variation strength: gamma = 10 noise / mean_i sum_j
 *  sqrt(w_ij), a length in the points' units (each edge's dual is bounded by gamma, so
 *  a point moves by at most gamma sum_j sqrt(w_ij) per unit of the data term).
 *  Calibrated as defaultTikhonovGamma. 0 when the graph has no edges or no noise. */
double
defaultTotalVariationGamma (const PointGraph &graph, double noise);

/** \brief The factor by which the refined filters (normals displacement onto local
 *  quadrics) scale the rule's strength for the surface's detail: the detail length
 *  1 / curvature (NoiseEstimate::curvature) in units of the graph's spacing, divided by
 *  40 for Tikhonov and by 30 for total variation, held within [1/8, 16]. A surface that
 *  stays smooth over many spacings (a sphere of 10,000 points: about 4) takes a stronger
 *  smoothing than one with detail at a few spacings (the mechanical parts and statues
 *  of the evaluation at 10,000 points: 1/4 to 1), and the same surface takes more when
 *  sampled more densely. Measured as the best multiple of the rule per cloud on two sets
 *  of meshes (docs/evaluation.md, section 5). 16 when the curvature is 0 (no bending
 *  measured above the noise: a plane, or a surface whose bending the noise buries); 1 when
 *  it was not measured (negative) or the graph has no spacing. */
double
detailGammaFactor (const PointGraph &graph, double curvature, SmoothingKind kind);

/** \brief The factor by which the refined total-variation filter scales its rule's
 *  strength for the noise-to-spacing ratio r = noise / spacing: (r / 0.5)^1.5, held
 *  within [1/2, 3]. The linear-in-noise TV rule under-smooths dense clouds with strong
 *  noise (the best multiple of the rule grows from about 1/2 at r = 0.25 to 4 and more
 *  at r = 1.2 on the calibration meshes; docs/evaluation.md, section 5); Tikhonov's rule
 *  already goes as r^1.5. 1 for the Tikhonov kinds, and when the noise is not positive
 *  and finite or the graph has no spacing. */
double
noiseGammaFactor (const PointGraph &graph, double noise, SmoothingKind kind);

/** \brief The refined filters' scale of the halved rule: detailGammaFactor times
 *  noiseGammaFactor, the product held within the detail term's own bounds [1/8, 16]
 *  (on a noisy sphere of a million points TV's product reaches 16, and 4 times that
 *  strength would still lower its error: docs/evaluation.md, section 5). */
double
refinedGammaFactor (const PointGraph &graph, double noise, double curvature, SmoothingKind kind);

/** \brief The refined filters' factor for noise far beyond the range the rules were
 *  calibrated on (noise up to about twice the spacing): with r = noise / surface_spacing
 *  (NoiseEstimate::level over NoiseEstimate::spacing, the spacing of the surface itself,
 *  not the k-NN distance, which grows with the noise), r / 4 for total variation and
 *  4 / r for Tikhonov where r > 4, else 1 (also when either is not positive and finite).
 *  Applied on top of refinedGammaFactor, beyond its bounds. On spheres, cubes, the bunny
 *  and fandisk at 20,000 and 100,000 points with noise of 4 to 8 spacings, TV's best
 *  multiple of its rule grows with r (x1.4-4 at 8 spacings) and Tikhonov's falls (x0.5
 *  at 8); docs/evaluation.md, section 5. */
double
highNoiseGammaFactor (double noise, double surface_spacing, SmoothingKind kind);

/** \brief The power of core::normalizeDensity (operators.h) for noise `noise` on a surface of point spacing
 *  `surface_spacing` (NoiseEstimate::level and NoiseEstimate::spacing): 1 up to 2.5
 *  spacings of noise, 0 from 3.5 on, linear between; 1 when either is not positive and
 *  finite. Under noise of several spacings the degrees measure the noise's scatter more
 *  than the sampling, and dividing them out moved the refined Tikhonov filter's rule onto
 *  the edge where a stronger gamma collapses the surface (a sphere of 50,000 points at 6%
 *  noise, 3.8 spacings: error 0.0053 -> 0.0121); docs/evaluation.md, section 5. */
double
densityNormalizationPower (double noise, double surface_spacing);

/** \brief A whole denoising pass at a strength gamma: the positions of the points of
 *  `graph` (one row per vertex) denoised, as the filters do (solve, refinements). */
using Denoiser = std::function<Signal3 (const PointGraph &graph, const Signal3 &f, double gamma)>;

/** \brief Settings of selectGammaByRisk. */
struct RiskSelectionParams
{
  /** Multiples of the given gamma tried first (ascending); the best is then refined by
   *  one step of sqrt 2 on each side. */
  std::vector<double> multiples = {0.25, 0.5, 1.0, 2.0, 4.0, 8.0, 16.0};
  /** At most this many vertices take part: larger graphs are sampled in four blocks of
   *  consecutive (hence spatially compact) vertices, which keep the density. */
  std::size_t sample_size = 50000;
  std::uint64_t seed = 1;  ///< of the random probe (results are deterministic)
  int num_threads = 0;     ///< for the normals; 0 = all hardware threads
};

/** \brief Chooses the denoising strength by Stein's unbiased risk estimate: among
 *  gamma x multiples, the one whose expected squared error along the surface normal,
 *
 *    R(gamma) = sum_i (n_i . (x_i - f_i))^2 - N noise^2 + 2 noise^2 div_n(gamma),
 *
 *  is lowest, where x = denoise(f, gamma), n_i the normals of the points denoised at the
 *  given gamma and div_n the divergence of the denoiser along those normals, estimated
 *  by one random probe (f + noise z_i n_i, z standard normal: a step of the noise's own
 *  size also catches the jumps of the robust fits that a small step misses). Needs no
 *  ground truth, only the noise level (Gaussian noise of that standard deviation per
 *  axis). Sums run over the vertices whose neighbours all take part. Returns `gamma`
 *  itself when it, the noise or the graph is empty.
 *  \throws std::invalid_argument when f has the wrong size or the parameters are invalid. */
double
selectGammaByRisk (const PointGraph &graph, const Signal3 &f, double noise, double gamma,
                   const Denoiser &denoise, const RiskSelectionParams &params = {});

} // namespace core
} // namespace pcl_graph_denoise

/*
 * pcl_graph_denoise: graph-signal-processing point cloud denoising for PCL.
 * SPDX-License-Identifier: BSD-3-Clause
 */
#pragma once

#include <pcl_graph_denoise/core/graph.h>
#include <pcl_graph_denoise/core/memory.h>
#include <pcl_graph_denoise/core/operators.h>
#include <pcl_graph_denoise/core/solvers.h>

#include <pcl/filters/filter.h>

#include <functional>
#include <string>

namespace pcl_graph_denoise {

/** \brief The local surface a smoothing filter moves each point onto, along its normal
 *  (GraphSmoothing::setLocalSurface). */
enum class LocalSurface
{
  PLANE,            ///< the plane fitted to the smoothed points over two graph rings
  QUADRIC,          ///< a quadric height field fitted robustly to the smoothed points over two
                    ///< rings (or three: GraphSmoothing::setAdaptiveSupport)
  BLENDED_QUADRICS  ///< the weighted mean of the quadrics of the point's two rings (default)
};

/** \brief How the data-derived strength is chosen (GraphSmoothing::setGammaSelection). */
enum class GammaSelection
{
  RULE,          ///< a closed-form rule in the noise level, spacing and degrees (default)
  RISK_ESTIMATE  ///< the multiple of the rule's gamma with the lowest estimated error
};

/** \brief The largest number of passes GraphSmoothing::setGraphIterations accepts: every
 *  pass runs, so a huge count (INT_MAX) would run for ever. */
constexpr int kMaxGraphIterations = 1000;

/** \brief What a smoothing filter reports while it runs (GraphSmoothing::setProgressCallback). */
struct SmoothingProgress
{
  /** \brief Where the filter is. */
  enum Stage
  {
    GRAPH_BUILT,  ///< a pass's graph is built: `vertices` and `edges` are set
    SOLVING       ///< the solver is running: `iterations` and `residual` are set
  };
  Stage stage = GRAPH_BUILT;  ///< where the filter is
  int pass = 0;               ///< the pass, from 0 (setGraphIterations)
  std::size_t vertices = 0;   ///< GRAPH_BUILT: points in the graph
  std::size_t edges = 0;      ///< GRAPH_BUILT: undirected edges
  int iterations = 0;         ///< SOLVING: iterations done in the current solve
  double residual = 0.0;      ///< SOLVING: the solver's stopping measure (setTolerance) now
};

template <typename PointT>
class GraphSequenceSmoothing;

/** \brief What the graph smoothing filters share: the k-NN graph of the points, the
 *  data-derived strength, re-graphing, and the PCL contract of a smoother.
 *
 * Output follows PCL's smoothing filters (Bilateral, Median): it starts as a copy of
 * the input, and only x, y, z of the finite points named by the indices are rewritten
 * (each moved by its computed displacement). As in those filters, the whole cloud is
 * searched: the graph links every finite point of the input, and a named point moves as
 * when the whole cloud is smoothed (so a small region of a large cloud costs the whole
 * cloud's time; extract it first, e.g. with pcl::ExtractIndices, to smooth it on its
 * own). Coincident points (exact copies) are one vertex, and every copy moves as one.
 * Size, organisation and every other field
 * are kept, non-finite points pass through unchanged, as do a few points with garbage
 * coordinates (more than 5e17 from the others' median along an axis; with a PCL_WARN), a
 * point with no neighbour does not move and gamma = 0 is the identity. Invalid parameters or indices print a
 * PCL_ERROR naming the class and the parameter and leave an empty output; a solver
 * that stops before its tolerance prints a PCL_WARN with the residual reached and
 * keeps its best iterate. Nothing throws out of filter().
 *
 * Subclasses provide the solver (GraphTikhonovSmoothing, GraphTVSmoothing). By default
 * two refinements beyond the paper apply on top of it (see setNormalDisplacement and
 * setShrinkageCorrection, measured in docs/evaluation.md); turning both off gives the
 * paper's filter exactly.
 */
template <typename PointT>
class GraphSmoothing : public pcl::Filter<PointT>
{
  /** The sequence smoother runs this filter's passes on its spatio-temporal graph. */
  friend class GraphSequenceSmoothing<PointT>;

protected:
  using PointCloud = typename pcl::Filter<PointT>::PointCloud;  ///< the cloud type filtered
  using pcl::Filter<PointT>::fake_indices_;
  using pcl::Filter<PointT>::use_indices_;
  using pcl::Filter<PointT>::filter_name_;
  using pcl::Filter<PointT>::getClassName;
  using pcl::Filter<PointT>::indices_;
  using pcl::Filter<PointT>::input_;

public:
  using Ptr = std::shared_ptr<GraphSmoothing<PointT>>;  ///< shared pointer, as PCL's filters
  using ConstPtr = std::shared_ptr<const GraphSmoothing<PointT>>;  ///< shared pointer to const

  /** \brief Number of nearest neighbours of each point in the graph (the graph links i
   *  and j when either is among the other's k nearest). Default 10. Valid: >= 1; with
   *  fewer than k + 1 points, every point links to all others. On such dense graphs
   *  (k beyond about 60) the local surfaces of the noise estimate, the normals and the
   *  quadrics take a point's neighbours only, at most its 1024 nearest, instead of its
   *  two graph rings, so that their time stays linear in k. A k far above 30 also widens
   *  those local surfaces past the surface's curvature: on a 5,000-point noisy sphere the
   *  noise estimate was 5 times the noise at k = 100, and at k = 1000 the output was
   *  noisier than the input. */
  inline void
  setKSearch (int k) { k_ = k; }

  /** \brief The number of neighbours set. */
  inline int
  getKSearch () const { return k_; }

  /** \brief Kernel width theta of the weights exp(-d^2 / (2 theta^2)), in the cloud's
   *  units. Default 0 = derived from the data: mean k-NN distance / sqrt(2).
   *  Valid: finite, >= 0. */
  inline void
  setSigma (double theta) { sigma_ = theta; }

  /** \brief The kernel width set (0 = derived from the data). */
  inline double
  getSigma () const { return sigma_; }

  /** \brief Smoothing strength gamma (see the subclass for its unit). Setting it turns
   *  off the data-derived default; 0 leaves the cloud unchanged. gamma sets the graph
   *  solve's strength; the local-surface step after it (setNormalDisplacement,
   *  setLocalSurface) smooths on its own, so that a gamma near 0 still moves the points
   *  onto the surfaces fitted to them (in the paper's filter, without that step, gamma ->
   *  0 is the identity). Valid: finite, >= 0. A gamma
   *  too large for double precision (for Tikhonov on a unit sphere, about 1e20), whose
   *  solve would return points outside the cloud's bounding box, is an error (empty
   *  output) rather than such a cloud. */
  inline void
  setGamma (double gamma)
  {
    gamma_ = gamma;
    automatic_gamma_ = false;
  }

  /** \brief The gamma set (meaningful when getAutomaticGamma() is false). */
  inline double
  getGamma () const { return gamma_; }

  /** \brief Derive gamma from the data at each filter() call (the default): from the
   *  estimated noise level, the point spacing and the graph's degrees. */
  inline void
  setAutomaticGamma () { automatic_gamma_ = true; }

  /** \brief True when gamma is derived from the data. */
  inline bool
  getAutomaticGamma () const { return automatic_gamma_; }

  /** \brief How the automatic gamma is chosen. GammaSelection::RULE (default): the
   *  closed-form rule (see the subclass). GammaSelection::RISK_ESTIMATE: the filter runs
   *  at the rule's gamma times 1/4, 1/2, ... 16 (then one step of sqrt 2 around the best)
   *  and keeps the one with the lowest Stein unbiased estimate of its error along the
   *  normals, which needs no ground truth (core::selectGammaByRisk). It follows what the
   *  surface's detail allows at every scale, where the rule's detail term reads only
   *  bending wider than about 12 spacings (less smoothing on thin parts, more on smooth
   *  ones); it costs about 18 extra runs on at most 50,000 points (four
   *  blocks of the cloud when larger). Assumes noise of the same level everywhere. Where
   *  the noise is larger than the point spacing it chooses too little smoothing
   *  (docs/evaluation.md, section 5). Used only while gamma is automatic. */
  inline void
  setGammaSelection (GammaSelection selection) { gamma_selection_ = selection; }

  /** \brief How the automatic gamma is chosen. */
  inline GammaSelection
  getGammaSelection () const { return gamma_selection_; }

  /** \brief Number of passes: each pass rebuilds the graph on the previous pass's output
   *  and denoises it again (the paper's re-graphing). Default 1. Valid: 1 to
   *  kMaxGraphIterations (1000). */
  inline void
  setGraphIterations (int n) { graph_iterations_ = n; }

  /** \brief The number of passes set. */
  inline int
  getGraphIterations () const { return graph_iterations_; }

  /** \brief Move each point only along its estimated surface normal (default true),
   *  onto a local surface fitted to the smoothed points (setLocalSurface). Points then
   *  do not drift along the surface (no clustering, no holes opening at borders and
   *  thin parts), the main error of plain graph smoothing against the true surface.
   *  false = the paper's free displacement. */
  inline void
  setNormalDisplacement (bool along_normal) { normal_displacement_ = along_normal; }

  /** \brief Whether points move only along their normals. */
  inline bool
  getNormalDisplacement () const { return normal_displacement_; }

  /** \brief The surface each point moves onto with normal displacement on.
   *  LocalSurface::BLENDED_QUADRICS (default): around the vertices that setPatchCover
   *  picks (about 40% of them), a quadric height field fitted over two graph rings of the smoothed points (three where that agrees:
   *  setAdaptiveSupport, on by default), robustly re-weighted by the estimated noise level so that the
   *  far side of a thin wall or the other face at an edge does not pull it; each point moves onto the weighted mean of the quadrics of
   *  its two rings (weights: its distance to each patch's centre and to its surface), so
   *  that the overlapping fits average out their own noise (core::quadricDisplacement
   *  with core::QuadricProjection::BLENDED). LocalSurface::QUADRIC: onto its own vertex's
   *  quadric only, the previous default. With either, the data-derived gamma is half the
   *  paper rule's (the fits remove noise themselves; a quarter with setAdaptiveSupport on)
   *  times the detail term, and for TV the noise term (core::refinedGammaFactor).
   *  LocalSurface::PLANE: the plane through the smoothed point, normal from the fit of the smoothed points over two rings
   *  (core::normalDisplacement). All measured in docs/evaluation.md. */
  inline void
  setLocalSurface (LocalSurface surface) { local_surface_ = surface; }

  /** \brief The local surface set. */
  inline LocalSurface
  getLocalSurface () const { return local_surface_; }

  /** \brief Fit each quadric over a support chosen per vertex (default true): over
   *  two graph rings, and over three where that wider fit agrees with the two-ring one
   *  (their surfaces, under the two-ring points, within 2 sqrt(6) noise levels in
   *  root-sum-square: core::QuadricSupport::ADAPTIVE), so that smooth parts average more
   *  noise while edges, thin parts and fine detail keep the narrow fit. false = two rings
   *  everywhere, in 0.6-1.0 times the smoothing's time. The data-derived gamma is halved again with it (the wider fits
   *  remove more noise). Applies to the quadric surfaces only (setLocalSurface; no effect
   *  with LocalSurface::PLANE or normal displacement off). docs/evaluation.md section 5
   *  has its measurements. */
  inline void
  setAdaptiveSupport (bool adaptive) { adaptive_support_ = adaptive; }

  /** \brief Whether the quadrics' support is chosen per vertex. */
  inline bool
  getAdaptiveSupport () const { return adaptive_support_; }

  /** \brief Fit the blended quadrics at fewer vertices (default 3): in the graph's
   *  (Morton) order a vertex gets a quadric of its own unless `cover` of its graph
   *  neighbours already have one, and each point blends the quadrics of its two rings
   *  (core::patchCentres). The fits overlap so much that blending about 40% of them
   *  costs little: on the calibration set 0.7% more error than a quadric at every
   *  vertex (0 = every vertex), for 0.6 times Tikhonov's time and 0.7 times TV's on a
   *  1,000,000-point sphere.
   *  Valid: >= 0. Applies to LocalSurface::BLENDED_QUADRICS only. docs/evaluation.md
   *  section 5 has its measurements. */
  inline void
  setPatchCover (int cover) { patch_cover_ = cover; }

  /** \brief The cover set (0 = a quadric at every vertex). */
  inline int
  getPatchCover () const { return patch_cover_; }

  /** \brief Divide the sampling density out of the graph's weights before smoothing
   *  (default true): w_ij becomes w_ij a_i a_j, a_i the mean weighted degree over vertex
   *  i's own, clamped to [1/16, 16] (core::normalizeDensity; Coifman and Lafon's
   *  normalisation with alpha = 1), so that a sparse part of the cloud (a scan's far part)
   *  is smoothed as much as a dense one, and on an even sampling the points that noise
   *  carried away from their neighbours are pulled in more. Under noise of several point
   *  spacings, where the degrees measure the noise's scatter, it fades out (from 2.5 to
   *  3.5 spacings: core::densityNormalizationPower). The gamma rule reads the Gaussian
   *  weights' degrees, before the division. Applies with normal displacement on
   *  (setNormalDisplacement; off, the filters are the paper's with its weights). On the
   *  calibration set 4.4% less error for Tikhonov and 4.0% for TV; on a square whose
   *  sampling density falls 30-fold, 42% less on its sparse half (docs/evaluation.md,
   *  section 5). false = the Gaussian weights. */
  inline void
  setDensityNormalization (bool normalize) { density_normalization_ = normalize; }

  /** \brief Whether the sampling density is divided out of the weights. */
  inline bool
  getDensityNormalization () const { return density_normalization_; }

  /** \brief Correct the shrinkage of curved surfaces (default true) by twicing: with
   *  H the smoothing, the result is 2 H(f) - H(H(f)), for Tikhonov the spectral
   *  filter 1 - (1 - h)^2 with h = 1 / (1 + 2 gamma lambda), flat to second order at
   *  low frequencies where the paper's h falls linearly. It costs a second solve of
   *  about the first one's cost. false = the paper's filter. */
  inline void
  setShrinkageCorrection (bool correct) { shrinkage_correction_ = correct; }

  /** \brief Whether the shrinkage correction is applied. */
  inline bool
  getShrinkageCorrection () const { return shrinkage_correction_; }

  /** \brief When the solver stops: the conjugate gradient's relative residual
   *  (Tikhonov) or the relative primal-dual gap (TV). Valid: finite, > 0. Until one is set, the
   *  default depends on the pipeline: where the points move onto fitted quadrics (the
   *  default local surface, setLocalSurface) the fit removes what a looser solve leaves,
   *  and the default is the subclass's looser one (Tikhonov 5e-4, TV 2e-2: on the
   *  calibration set the same error or less, far fewer iterations on a 1,000,000-point
   *  sphere; docs/evaluation.md); otherwise, for the paper's filters, the solvers' own
   *  (core::TikhonovParams: 1e-5, core::TotalVariationParams: 1e-3). A value set here is
   *  used in every pipeline. */
  inline void
  setTolerance (double tolerance)
  {
    tolerance_ = tolerance;
    tolerance_set_ = true;
  }

  /** \brief The tolerance the solver stops at: the one set, else the default for the
   *  pipeline as now configured (setTolerance). */
  inline double
  getTolerance () const
  {
    return !tolerance_set_ && fitsQuadrics () ? fitted_tolerance_ : tolerance_;
  }

  /** \brief Solver iteration cap per pass (Tikhonov default 1000, TV 500); a capped
   *  solve warns and keeps its last iterate. Valid: >= 1. */
  inline void
  setMaximumIterations (int iterations) { max_iterations_ = iterations; }

  /** \brief The iteration cap set. */
  inline int
  getMaximumIterations () const { return max_iterations_; }

  /** \brief Worker threads; 0 (default) = all hardware threads. The result does not
   *  depend on it. Valid: >= 0. */
  inline void
  setNumberOfThreads (int num_threads) { num_threads_ = num_threads; }

  /** \brief The number of threads set. */
  inline int
  getNumberOfThreads () const { return num_threads_; }

  /** \brief Memory the filter may use, in bytes (default 0: the machine's physical
   *  memory). filter() first estimates its peak for the input (estimateMemory) and,
   *  when that is above the limit, prints a PCL_ERROR with both figures and leaves an
   *  empty output, before allocating anything: a cloud too large fails at once rather
   *  than being killed half-way. */
  inline void
  setMemoryLimit (std::size_t bytes) { memory_limit_ = bytes; }

  /** \brief The memory limit set (0: the machine's physical memory). */
  inline std::size_t
  getMemoryLimit () const { return memory_limit_; }

  /** \brief Estimated peak memory, in bytes, of filtering a cloud of `num_points`
   *  points with the current parameters (the output cloud included, the input not):
   *  an upper bound of what bench/bench_memory measures (docs/reliability.md). */
  std::size_t
  estimateMemory (std::size_t num_points) const;

  /** \brief Called while filter() runs, from the calling thread: when each pass's graph
   *  is built (SmoothingProgress::GRAPH_BUILT), and every 10 iterations of the
   *  conjugate gradient or at each duality-gap check of TV (SmoothingProgress::SOLVING).
   *  For tools that report on long work (the command-line tool prints it); empty (the
   *  default) = nothing is called. The callback must not throw. */
  inline void
  setProgressCallback (const std::function<void (const SmoothingProgress &)> &callback)
  {
    progress_ = callback;
  }

  /** \brief Gamma used by the last pass of the last filter() call (0 after a call that
   *  failed, as are the other values it reports). */
  inline double
  getUsedGamma () const { return used_gamma_; }

  /** \brief Theta used by the last pass of the last filter() call. */
  inline double
  getUsedSigma () const { return used_sigma_; }

  /** \brief Noise level (standard deviation along the normal, cloud units) estimated
   *  by the first pass of the last filter() call; 0 when nothing needed it (gamma set
   *  explicitly, no quadric fit and no density normalisation). */
  inline double
  getEstimatedNoise () const { return estimated_noise_; }

  /** \brief How the last pass's graph fell apart (core::connectedComponents): separate
   *  objects or far clusters are separate components, each smoothed on its own, and a
   *  point whose every edge weight underflowed is isolated and does not move. Also
   *  printed with PCL_DEBUG. */
  inline const core::GraphComponents &
  getGraphComponents () const { return components_; }

  /** \brief What the solver reported in the last pass: iterations summed over its
   *  solves (two with the shrinkage correction), the largest final residual, and
   *  whether every solve converged. */
  inline const core::SolverReport &
  getSolverReport () const { return report_; }

protected:
  /** \brief The subclass gives its solver's default tolerance, the looser default used
   *  where quadrics are fitted (setTolerance) and its iteration cap. */
  GraphSmoothing (double tolerance, double fitted_tolerance, int max_iterations)
  : tolerance_ (tolerance), fitted_tolerance_ (fitted_tolerance), max_iterations_ (max_iterations)
  {}

  /** \brief Whether the points move onto fitted quadrics (normal displacement onto a
   *  LocalSurface other than PLANE). */
  inline bool
  fitsQuadrics () const { return normal_displacement_ && local_surface_ != LocalSurface::PLANE; }

  /** \brief pcl::Filter's entry point: gathers the finite points named by the indices
   *  and the cloud's other finite points (searched as neighbours), merges exact copies,
   *  runs the passes (graph, gamma, smoother(), displacement) and writes x, y, z of the
   *  named points back into a copy of the input. */
  void
  applyFilter (PointCloud &output) override;

  /** \brief Estimated peak memory of smoothing `num_points` points on a graph of about
   *  `neighbours` neighbours per point (estimateMemory with k). */
  std::size_t
  estimateMemoryFor (std::size_t num_points, std::size_t neighbours) const;

  /** \brief Why the parameters are invalid (naming the setter), or empty when valid. */
  std::string
  invalidParameters () const;

  /** \brief Builds a pass's graph on the current positions (one row per point). */
  using GraphBuilder = std::function<core::PointGraph (const core::PointMatrix &)>;

  /** \brief Runs the passes on `start` (one row per point, relative coordinates): each
   *  builds its graph with `build_graph` on the current positions, derives gamma, solves
   *  with smoother() and applies the refinements; returns the final positions in the same
   *  rows. Sets the used_ and last-call members. The graph may be any PointGraph over
   *  the rows (GraphSequenceSmoothing gives the spatio-temporal one).
   *  \throws std::exception from the core (invalid sizes, memory). */
  core::Signal3
  runPasses (const core::Signal3 &start, const GraphBuilder &build_graph);

  /** \brief One denoising of a signal f (graph vertex order), reporting its solve. */
  using Smoother = std::function<core::Signal3 (const core::Signal3 &f, core::SolverReport &report)>;

  /** \brief The denoiser of `graph` at strength gamma, set up once for every signal it is
   *  given (the shrinkage correction solves twice on one graph and gamma). The graph must
   *  outlive it; it and its copies are not for concurrent calls.
   *  \throws std::exception from the core (invalid parameters, a failed factorisation). */
  virtual Smoother
  smoother (const core::PointGraph &graph, double gamma) const = 0;

  /** \brief The solver's progress callback for smoother(): reports SOLVING events of the
   *  current pass through setProgressCallback's callback; empty when none is set. */
  std::function<void (int, double)>
  solverProgress () const;

  /** \brief Which computation smoother() runs, for the memory estimate. */
  virtual core::SmoothingKind
  smoothingKind () const = 0;

  /** \brief The data-derived gamma for a graph and an estimated noise level. */
  virtual double
  automaticGamma (const core::PointGraph &graph, double noise) const = 0;

  int k_ = 10;                    ///< setKSearch
  double sigma_ = 0.0;            ///< setSigma (0 = derived)
  double gamma_ = 0.0;            ///< setGamma
  bool automatic_gamma_ = true;   ///< setAutomaticGamma / setGamma
  GammaSelection gamma_selection_ = GammaSelection::RULE;  ///< setGammaSelection
  int graph_iterations_ = 1;      ///< setGraphIterations
  bool normal_displacement_ = true;                      ///< setNormalDisplacement
  LocalSurface local_surface_ = LocalSurface::BLENDED_QUADRICS;  ///< setLocalSurface
  bool adaptive_support_ = true;                         ///< setAdaptiveSupport
  int patch_cover_ = 3;                                  ///< setPatchCover
  bool shrinkage_correction_ = true;                     ///< setShrinkageCorrection
  bool density_normalization_ = true;                    ///< setDensityNormalization
  double tolerance_;              ///< setTolerance, or the solver's own default
  double fitted_tolerance_;       ///< the default where quadrics are fitted (setTolerance)
  bool tolerance_set_ = false;    ///< setTolerance was called
  int max_iterations_;            ///< setMaximumIterations
  int num_threads_ = 0;           ///< setNumberOfThreads
  std::size_t memory_limit_ = 0;  ///< setMemoryLimit (bytes, 0 = physical memory)
  std::function<void (const SmoothingProgress &)> progress_;  ///< setProgressCallback
  int current_pass_ = 0;          ///< the pass runPasses is in, for solverProgress

  double used_gamma_ = 0.0;           ///< getUsedGamma
  double used_sigma_ = 0.0;           ///< getUsedSigma
  double estimated_noise_ = 0.0;      ///< getEstimatedNoise
  core::SolverReport report_;         ///< getSolverReport
  core::GraphComponents components_;  ///< getGraphComponents
};

} // namespace pcl_graph_denoise

#ifdef PCL_NO_PRECOMPILE
#include <pcl_graph_denoise/impl/graph_smoothing.hpp>
#endif

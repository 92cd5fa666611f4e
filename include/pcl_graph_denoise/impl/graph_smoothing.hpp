/*
 * pcl_graph_denoise: graph-signal-processing point cloud denoising for PCL.
 * SPDX-License-Identifier: BSD-3-Clause
 */
#pragma once

#include <pcl_graph_denoise/core/noise_level.h>
#include <pcl_graph_denoise/core/normals.h>
#include <pcl_graph_denoise/core/operators.h>
#include <pcl_graph_denoise/graph_smoothing.h>
#include <pcl_graph_denoise/point_cloud_adaptor.h>

#include <pcl/console/print.h>

#include <algorithm>
#include <cmath>
#include <exception>
#include <limits>
#include <string>

namespace pcl_graph_denoise {

namespace detail {
/** The data-derived gamma rules (core/default_gamma.cpp) are calibrated for the paper's
 *  filters; with the quadric fit, which removes part of the noise itself, the best gamma
 *  measured on meshes is about half (docs/evaluation.md). */
constexpr double kQuadricGammaScale = 0.5;
/** With the adaptive support (setAdaptiveSupport) the wider fits remove more of the
 *  noise, and the best gamma on the calibration set is about half again: the constant
 *  multiple of 1/4 to 16 with the lowest geometric-mean error over the best of the sweep
 *  was 1/2 for TV and 0.35-0.5 for Tikhonov at 10,000 points (docs/evaluation.md). */
constexpr double kAdaptiveSupportGammaScale = 0.5;
} // namespace detail

template <typename PointT>
std::size_t
GraphSmoothing<PointT>::estimateMemory (std::size_t num_points) const
{
  return estimateMemoryFor (num_points, k_ > 0 ? std::size_t (k_) : 1);
}

template <typename PointT>
std::size_t
GraphSmoothing<PointT>::estimateMemoryFor (std::size_t num_points, std::size_t neighbours) const
{
  // The PCL layer: the output cloud, the gathered points and their indices, the start
  // and current positions in double.
  const long double layer = static_cast<long double> (num_points) * (sizeof (PointT) + 20 + 48);
  const long double core = core::smoothingMemory (num_points, neighbours, smoothingKind ());
  const long double most = static_cast<long double> (std::numeric_limits<std::size_t>::max ());
  return layer + core >= most ? std::numeric_limits<std::size_t>::max ()
                              : static_cast<std::size_t> (layer + core);
}

template <typename PointT>
std::string
GraphSmoothing<PointT>::invalidParameters () const
{
  if (k_ < 1)
    return "k (setKSearch) = " + std::to_string (k_) + ": must be >= 1";
  if (!(std::isfinite (sigma_) && sigma_ >= 0.0))
    return "sigma (setSigma) = " + std::to_string (sigma_) + ": must be finite and >= 0";
  if (!automatic_gamma_ && !(std::isfinite (gamma_) && gamma_ >= 0.0))
    return "gamma (setGamma) = " + std::to_string (gamma_) + ": must be finite and >= 0";
  if (graph_iterations_ < 1 || graph_iterations_ > kMaxGraphIterations)
    return "graph iterations (setGraphIterations) = " + std::to_string (graph_iterations_) +
           ": must be in [1, " + std::to_string (kMaxGraphIterations) + "]";
  if (patch_cover_ < 0)
    return "patch cover (setPatchCover) = " + std::to_string (patch_cover_) + ": must be >= 0";
  if (num_threads_ < 0)
    return "number of threads (setNumberOfThreads) = " + std::to_string (num_threads_) +
           ": must be >= 0";
  if (const double tolerance = getTolerance (); !(std::isfinite (tolerance) && tolerance > 0.0))
    return "tolerance (setTolerance) = " + std::to_string (tolerance) + ": must be finite and > 0";
  if (max_iterations_ < 1)
    return "maximum iterations (setMaximumIterations) = " + std::to_string (max_iterations_) +
           ": must be >= 1";
  return {};
}

template <typename PointT>
std::function<void (int, double)>
GraphSmoothing<PointT>::solverProgress () const
{
  if (!progress_)
    return {};
  return [this] (int iterations, double residual) {
    SmoothingProgress event;
    event.stage = SmoothingProgress::SOLVING;
    event.pass = current_pass_;
    event.iterations = iterations;
    event.residual = residual;
    progress_ (event);
  };
}

template <typename PointT>
void
GraphSmoothing<PointT>::applyFilter (PointCloud &output)
{
  const std::string name = getClassName ();
  // What this call used: nothing until it gets there (a failed call reports nothing).
  used_gamma_ = used_sigma_ = estimated_noise_ = 0.0;
  report_ = core::SolverReport{};
  components_ = core::GraphComponents{};
  const auto fail = [&] () {
    output.clear ();
    output.width = output.height = 0;
    output.is_dense = true;
  };
  std::string invalid = invalidParameters ();
  if (invalid.empty ())
  {
    const std::string bad_index = checkIndices (*input_, *indices_);
    if (!bad_index.empty ())
      invalid = "indices: " + bad_index;
  }
  if (!invalid.empty ())
  {
    PCL_ERROR ("[pcl_graph_denoise::%s::applyFilter] Invalid %s.\n", name.c_str (),
               invalid.c_str ());
    return fail ();
  }

  try
  {
    core::requireMemory (estimateMemory (input_->size ()), memory_limit_,
                         "smoothing " + std::to_string (input_->size ()) + " points with k = " +
                             std::to_string (k_));
  }
  catch (const std::exception &e)
  {
    PCL_ERROR ("[pcl_graph_denoise::%s::applyFilter] %s.\n", name.c_str (), e.what ());
    return fail ();
  }

  output = *input_;
  GatheredPoints gathered = gatherFinitePoints (*input_, *indices_, name.c_str ());
  if (gathered.cloud_index.empty ())
  {
    PCL_ERROR ("[pcl_graph_denoise::%s::applyFilter] Nothing to smooth: %s; the input is "
               "returned unchanged.\n",
               name.c_str (),
               noFinitePointReason (input_->size (), indices_->size (), !fake_indices_).c_str ());
    return;
  }
  if (!automatic_gamma_ && gamma_ == 0.0)
    return;  // the identity
  takeOutFarPoints (*input_, gathered, name.c_str (), "they stay where they are");
  addSearchSurface (*input_, gathered, name.c_str ());

  // Coincident points are one vertex: k copies of a point would otherwise fill its k
  // neighbours and nothing could move. Every copy gets its position's result.
  const core::DistinctPoints distinct = core::distinctPoints (gathered.xyz);
  const core::Signal3 start =
      (distinct.copies > 0 ? distinct.points : gathered.xyz).template cast<double> ();
  core::Signal3 position;
  try
  {
    core::KnnGraphParams params;
    params.k = k_;
    params.sigma = sigma_;
    params.num_threads = num_threads_;
    params.memory_limit = memory_limit_;
    position = runPasses (start, [&] (const core::PointMatrix &points) {
      return core::buildKnnGraph (points, params);
    });
  }
  catch (const std::exception &e)
  {
    PCL_ERROR ("[pcl_graph_denoise::%s::applyFilter] %s.\n", name.c_str (), e.what ());
    // A failed call reports nothing, also when it failed in a solve.
    used_gamma_ = used_sigma_ = estimated_noise_ = 0.0;
    report_ = core::SolverReport{};
    components_ = core::GraphComponents{};
    return fail ();
  }
  core::Signal3 copies_start;  // with copies: every row's start (else `start` is)
  if (distinct.copies > 0)
  {
    core::Signal3 moved (gathered.xyz.rows (), 3);
    for (Eigen::Index r = 0; r < moved.rows (); ++r)
      moved.row (r) = position.row (distinct.of_row[static_cast<std::size_t> (r)]);
    position = std::move (moved);
    copies_start = gathered.xyz.template cast<double> ();
  }
  if (!writeDisplacements (gathered.cloud_index, distinct.copies > 0 ? copies_start : start,
                           position, output))
  {
    PCL_ERROR ("[pcl_graph_denoise::%s::applyFilter] The smoothed positions overflowed: "
               "gamma = %g is too large.\n", name.c_str (), used_gamma_);
    return fail ();
  }
}

template <typename PointT>
core::Signal3
GraphSmoothing<PointT>::runPasses (const core::Signal3 &start, const GraphBuilder &build_graph)
{
  const std::string name = getClassName ();
  const std::size_t count = static_cast<std::size_t> (start.rows ());
  core::Signal3 position = start;
  for (int pass = 0; pass < graph_iterations_; ++pass)
  {
    current_pass_ = pass;
    core::PointGraph graph = build_graph (position.template cast<float> ());
    if (progress_)
    {
      SmoothingProgress event;
      event.stage = SmoothingProgress::GRAPH_BUILT;
      event.pass = pass;
      event.vertices = graph.numVertices ();
      event.edges = graph.numEdges ();
      progress_ (event);
    }
    core::Signal3 f (static_cast<Eigen::Index> (count), 3);
    for (std::size_t v = 0; v < count; ++v)
      f.row (v) = position.row (graph.order[v]);
    used_sigma_ = graph.sigma;
    used_gamma_ = gamma_;
    components_ = core::connectedComponents (graph, num_threads_);
    // Most points without a link of weight above 0 (a theta far below the spacing, e.g.
    // given in metres for a cloud in millimetres): say so, they stay where they are.
    if (2 * components_.isolated > count && count > 1 && graph.spacing > 0.0)
      PCL_WARN ("[pcl_graph_denoise::%s::applyFilter] %zu of %zu points have no neighbour "
                "with a weight above 0 at theta = %g (their mean distance to their k "
                "nearest neighbours is %g) and stay where they are: theta (setSigma) is too "
                "small for this cloud.\n",
                name.c_str (), components_.isolated, count, graph.sigma, graph.spacing);
    else if (components_.count > 1)
      PCL_DEBUG ("[pcl_graph_denoise::%s::applyFilter] The graph of %zu points has %zu "
                 "connected components (largest %zu points, %zu isolated points that do "
                 "not move); each is smoothed on its own.\n",
                 name.c_str (), count, components_.count, components_.largest,
                 components_.isolated);
    const bool quadric = fitsQuadrics ();
    const bool normalizes = density_normalization_ && normal_displacement_;
    core::NoiseEstimate estimate;
    if (automatic_gamma_ || quadric || normalizes)
    {
      // Re-estimated on each pass: the noise left after the previous one.
      estimate = core::estimateNoise (graph, f, num_threads_);
      if (pass == 0)
        estimated_noise_ = estimate.level;
    }
    const double noise = estimate.level;
    // One denoising at a strength: the solve, twicing and the local surface. The report
    // keeps the solves of the pass's own run; the selection's runs are not reported.
    const auto denoise = [&] (const core::PointGraph &g, const core::Signal3 &signal, double gamma,
                              bool record) {
      // Set up once for both solves of twicing, and released before the local surface.
      Smoother smooth = smoother (g, gamma);
      const auto solve = [&] (const core::Signal3 &s) {
        core::SolverReport report;
        core::Signal3 solved = smooth (s, report);
        if (!record)
          return solved;
        // Each solve warns on its own when it stops before its tolerance; the report
        // sums the iterations of the pass and keeps the worst residual.
        if (!report.converged)
          PCL_WARN ("[pcl_graph_denoise::%s::applyFilter] The solver stopped after %d iterations "
                    "at a residual of %g, above its tolerance; its last iterate (TV: or its "
                    "start, where that was better) is used.\n",
                    name.c_str (), report.iterations, report.residual);
        report_.iterations += report.iterations;
        report_.residual = std::max (report_.residual, report.residual);
        report_.converged = report_.converged && report.converged;
        return solved;
      };
      const core::Signal3 smoothed = solve (signal);
      core::Signal3 x = shrinkage_correction_ ? solve (smoothed) : smoothed;
      if (shrinkage_correction_)
        x = 2.0 * smoothed - x;  // in place: no third signal while the solver's arrays stay
      smooth = nullptr;
      if (quadric)
        x = core::quadricDisplacement (g, signal, x, noise, num_threads_,
                                       local_surface_ == LocalSurface::QUADRIC
                                           ? core::QuadricProjection::OWN_PATCH
                                           : core::QuadricProjection::BLENDED,
                                       adaptive_support_ ? core::QuadricSupport::ADAPTIVE
                                                         : core::QuadricSupport::TWO_RINGS,
                                       patch_cover_);
      else if (normal_displacement_)
        x = core::normalDisplacement (signal, x, core::estimateNormals (g, smoothed, num_threads_));
      return x;
    };
    if (automatic_gamma_)
    {
      // The refined filters scale the paper's rule for the surface's detail, and TV also
      // for the noise-to-spacing ratio.
      used_gamma_ = automaticGamma (graph, noise);
      if (quadric)
        used_gamma_ *= detail::kQuadricGammaScale *
                       (adaptive_support_ ? detail::kAdaptiveSupportGammaScale : 1.0) *
                       core::refinedGammaFactor (graph, noise, estimate.curvature, smoothingKind ()) *
                       core::highNoiseGammaFactor (noise, estimate.spacing, smoothingKind ());
    }
    // The sampling density divided out of the weights: after the noise estimate and the
    // rule, which read the Gaussian weights' degrees, and before every solve.
    if (normalizes)
      core::normalizeDensity (graph, core::densityNormalizationPower (noise, estimate.spacing),
                              num_threads_);
    if (automatic_gamma_ && gamma_selection_ == GammaSelection::RISK_ESTIMATE)
    {
      core::RiskSelectionParams params;
      params.num_threads = num_threads_;
      used_gamma_ = core::selectGammaByRisk (
          graph, f, noise, used_gamma_,
          [&] (const core::PointGraph &g, const core::Signal3 &s, double gamma) {
            return denoise (g, s, gamma, false);
          },
          params);
    }
    report_ = core::SolverReport{};
    report_.converged = true;
    const core::Signal3 x = denoise (graph, f, used_gamma_, true);
    for (std::size_t v = 0; v < count; ++v)
      position.row (graph.order[v]) = x.row (v);
  }
  return position;
}

} // namespace pcl_graph_denoise

#define PCL_INSTANTIATE_GraphSmoothing(T) template class pcl_graph_denoise::GraphSmoothing<T>;

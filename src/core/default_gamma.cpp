/*
 * pcl_graph_denoise: graph-signal-processing point cloud denoising for PCL.
 * SPDX-License-Identifier: BSD-3-Clause
 */
#include <pcl_graph_denoise/core/operators.h>
#include <pcl_graph_denoise/core/solvers.h>

#include <pcl_graph_denoise/core/normals.h>

#include "solver_support.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <random>
#include <stdexcept>

namespace pcl_graph_denoise {
namespace core {

namespace {

// Calibrated for the paper's filters on noisy spheres and cubes (20k and 100k points,
// noise 0.5%, 1% and 2% of the size) for the lowest geometric-mean distance to the true
// surface. bench/calibrate_gamma measures how far they land from the best gamma for the
// refined default filters on meshes (docs/evaluation.md, section 5).
constexpr double kTikhonovC = 20.0;
constexpr double kTikhonovExponent = 1.5;
constexpr double kTotalVariationC = 10.0;
// The refined filters' detail term (detailGammaFactor): the best multiple of the rule
// per cloud goes as the detail length over the spacing, divided by these (fitted to the
// calibration meshes at 2,500 to 50,000 points and the PU-GAN meshes at 10,000 and
// 50,000 together; docs/evaluation.md, section 5).
constexpr double kTikhonovDetailSpacings = 40.0;
constexpr double kTotalVariationDetailSpacings = 30.0;
constexpr double kDetailFactorMin = 0.125;
constexpr double kDetailFactorMax = 16.0;
// The refined TV filter's noise term (noiseGammaFactor): its best multiple grows as
// (noise / spacing / 0.5)^1.5 (fitted to the calibration meshes at 10,000 and 50,000
// points only; docs/evaluation.md, section 5).
constexpr double kTotalVariationNoiseRatio = 0.5;
constexpr double kTotalVariationNoiseExponent = 1.5;
constexpr double kNoiseFactorMin = 0.5;
constexpr double kNoiseFactorMax = 3.0;
// Noise over the surface's spacing above which highNoiseGammaFactor scales the rules
// (fitted to noisy spheres, cubes, the bunny and fandisk at 4-8 spacings of noise;
// docs/evaluation.md, section 5).
constexpr double kHighNoiseRatio = 4.0;
// Noise over the surface's spacing up to which densityNormalizationPower is 1 (it falls to
// 0 one spacing further; docs/evaluation.md, section 5).
constexpr double kDensityNormalizationFullBelow = 2.5;

/** noise / surface_spacing, the noise in surface spacings; 0 when either is not positive
 *  and finite (not measured). */
double
surfaceNoiseRatio (double noise, double surface_spacing)
{
  if (!(noise > 0.0) || !std::isfinite (noise) || !(surface_spacing > 0.0) ||
      !std::isfinite (surface_spacing))
    return 0.0;
  return noise / surface_spacing;
}

double
meanOf (const std::vector<double> &v)
{
  return v.empty () ? 0.0 : std::accumulate (v.begin (), v.end (), 0.0) / double (v.size ());
}

/** A block of consecutive vertices [first, last) as a graph of its own (the edges with
 *  both ends inside), its positions, and which of its vertices kept all their
 *  neighbours and have neighbours that did (the ones the risk is summed over). */
struct Block
{
  PointGraph graph;
  Signal3 f;
  std::vector<char> interior;
};

Block
makeBlock (const PointGraph &graph, const Signal3 &f, std::size_t first, std::size_t last)
{
  Block block;
  const std::size_t size = last - first;
  block.graph.sigma = graph.sigma;
  block.graph.spacing = graph.spacing;
  block.graph.order.resize (size);
  block.graph.row_ptr.reserve (size + 1);
  block.graph.row_ptr.push_back (0);
  std::vector<char> complete (size, 1);
  for (std::size_t v = first; v < last; ++v)
  {
    block.graph.order[v - first] = static_cast<VertexIndex> (v - first);
    for (std::uint64_t e = graph.row_ptr[v]; e < graph.row_ptr[v + 1]; ++e)
    {
      const std::size_t j = graph.col[e];
      if (j < first || j >= last)
      {
        complete[v - first] = 0;
        continue;
      }
      block.graph.col.push_back (static_cast<VertexIndex> (j - first));
      block.graph.weight.push_back (graph.weight[e]);
    }
    block.graph.row_ptr.push_back (block.graph.col.size ());
  }
  block.f = f.middleRows (static_cast<Eigen::Index> (first), static_cast<Eigen::Index> (size));
  block.interior = complete;
  for (std::size_t v = 0; v < size; ++v)
    for (std::uint64_t e = block.graph.row_ptr[v]; e < block.graph.row_ptr[v + 1] && block.interior[v]; ++e)
      block.interior[v] = complete[block.graph.col[e]];
  return block;
}

} // namespace

double
selectGammaByRisk (const PointGraph &graph, const Signal3 &f, double noise, double gamma,
                   const Denoiser &denoise, const RiskSelectionParams &params)
{
  const std::size_t n = graph.numVertices ();
  if (static_cast<std::size_t> (f.rows ()) != n)
    throw std::invalid_argument ("selectGammaByRisk: signal of the wrong size");
  if (params.multiples.empty () || params.sample_size == 0 || params.num_threads < 0 || !denoise)
    throw std::invalid_argument ("selectGammaByRisk: no multiples, no sample or no denoiser");
  for (double m : params.multiples)
    if (!(m > 0.0) || !std::isfinite (m))
      throw std::invalid_argument ("selectGammaByRisk: multiples must be finite and positive");
  if (!(gamma > 0.0) || !std::isfinite (gamma) || !(noise > 0.0) || !std::isfinite (noise) ||
      graph.numEntries () == 0)
    return gamma;

  // Four blocks of consecutive vertices, spread over the (Morton) order, or the whole graph.
  std::vector<Block> blocks;
  if (n <= params.sample_size)
    blocks.push_back (makeBlock (graph, f, 0, n));
  else
  {
    const std::size_t size = std::max<std::size_t> (1, params.sample_size / 4);
    for (std::size_t b = 0; b < 4; ++b)
    {
      const std::size_t centre = (2 * b + 1) * n / 8;
      const std::size_t first = centre - std::min (centre, size / 2);
      blocks.push_back (makeBlock (graph, f, first, std::min (n, first + size)));
    }
  }

  // The probe: a step of one noise level along the normals of the points denoised at
  // the given gamma.
  std::mt19937_64 rng (params.seed);
  std::normal_distribution<double> gaussian;
  std::vector<Signal3> at_gamma, normals, probe, moved;  // at_gamma: the run at multiple 1
  for (const Block &block : blocks)
  {
    at_gamma.push_back (denoise (block.graph, block.f, gamma));
    normals.push_back (estimateNormals (block.graph, at_gamma.back (), params.num_threads));
    Signal3 z (block.f.rows (), 3);
    for (Eigen::Index v = 0; v < z.rows (); ++v)
      z.row (v) = gaussian (rng) * normals.back ().row (v);
    moved.push_back (block.f + noise * z);
    probe.push_back (std::move (z));
  }

  const auto risk = [&] (double multiple) {
    double sum = 0.0;
    for (std::size_t b = 0; b < blocks.size (); ++b)
    {
      const Block &block = blocks[b];
      const Signal3 x = multiple == 1.0 ? at_gamma[b] : denoise (block.graph, block.f, multiple * gamma);
      const Signal3 x_moved = denoise (block.graph, moved[b], multiple * gamma);
      for (Eigen::Index v = 0; v < x.rows (); ++v)
        if (block.interior[static_cast<std::size_t> (v)])
        {
          const double residual = (x.row (v) - block.f.row (v)).dot (normals[b].row (v));
          // 2 noise^2 times the divergence's probe estimate (z . (x_moved - x) / noise).
          sum += residual * residual + 2.0 * noise * (x_moved.row (v) - x.row (v)).dot (probe[b].row (v));
        }
    }
    // A run that overflowed (a strength far too large) is never the best.
    return std::isfinite (sum) ? sum : std::numeric_limits<double>::infinity ();
  };

  std::vector<std::pair<double, double>> tried;  // (multiple, risk)
  for (double m : params.multiples)
    tried.emplace_back (m, risk (m));
  const auto best = [&] {
    return std::min_element (tried.begin (), tried.end (),
                             [] (const auto &a, const auto &b) { return a.second < b.second; })->first;
  };
  const double coarse = best ();
  for (double m : {coarse / std::sqrt (2.0), coarse * std::sqrt (2.0)})
  {
    const bool seen = std::any_of (tried.begin (), tried.end (), [&] (const auto &t) {
      return std::abs (t.first / m - 1.0) < 1e-6;
    });
    if (!seen)
      tried.emplace_back (m, risk (m));
  }
  return best () * gamma;
}

double
defaultTikhonovGamma (const PointGraph &graph, double noise)
{
  const double degree = meanOf (weightedDegree (graph));
  if (!(degree > 0.0) || !(graph.spacing > 0.0) || !(noise > 0.0))
    return 0.0;
  return kTikhonovC * std::pow (noise / graph.spacing, kTikhonovExponent) / degree;
}

double
defaultTotalVariationGamma (const PointGraph &graph, double noise)
{
  const double mean_root = meanOf (detail::rootDegree (graph));
  if (!(mean_root > 0.0) || !(graph.spacing > 0.0) || !(noise > 0.0))
    return 0.0;
  return kTotalVariationC * noise / mean_root;
}

double
detailGammaFactor (const PointGraph &graph, double curvature, SmoothingKind kind)
{
  if (!(curvature >= 0.0) || !std::isfinite (curvature) || !(graph.spacing > 0.0))
    return 1.0;  // not measured
  if (curvature == 0.0)
    return kDetailFactorMax;  // no bending above the noise: an unbounded detail length
  const double spacings = kind == SmoothingKind::TOTAL_VARIATION ? kTotalVariationDetailSpacings
                                                                 : kTikhonovDetailSpacings;
  const double factor = 1.0 / (curvature * graph.spacing * spacings);
  return std::clamp (factor, kDetailFactorMin, kDetailFactorMax);
}

double
noiseGammaFactor (const PointGraph &graph, double noise, SmoothingKind kind)
{
  if (kind != SmoothingKind::TOTAL_VARIATION || !(noise > 0.0) || !std::isfinite (noise) ||
      !(graph.spacing > 0.0))
    return 1.0;
  const double ratio = noise / graph.spacing / kTotalVariationNoiseRatio;
  return std::clamp (std::pow (ratio, kTotalVariationNoiseExponent), kNoiseFactorMin,
                     kNoiseFactorMax);
}

double
refinedGammaFactor (const PointGraph &graph, double noise, double curvature, SmoothingKind kind)
{
  return std::clamp (detailGammaFactor (graph, curvature, kind) * noiseGammaFactor (graph, noise, kind),
                     kDetailFactorMin, kDetailFactorMax);
}

double
highNoiseGammaFactor (double noise, double surface_spacing, SmoothingKind kind)
{
  const double excess = std::max (1.0, surfaceNoiseRatio (noise, surface_spacing) / kHighNoiseRatio);
  return kind == SmoothingKind::TOTAL_VARIATION ? excess : 1.0 / excess;
}

double
densityNormalizationPower (double noise, double surface_spacing)
{
  return std::clamp (kDensityNormalizationFullBelow + 1.0 - surfaceNoiseRatio (noise, surface_spacing),
                     0.0, 1.0);
}

} // namespace core
} // namespace pcl_graph_denoise

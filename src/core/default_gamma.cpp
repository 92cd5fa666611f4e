/*
 * pcl_graph_denoise: graph-signal-processing point cloud denoising for PCL.
 * SPDX-License-Identifier: BSD-3-Clause
 */
#include <pcl_graph_denoise/core/operators.h>
#include <pcl_graph_denoise/core/solvers.h>

#include <cmath>
#include <numeric>

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

double
meanOf (const std::vector<double> &v)
{
  return v.empty () ? 0.0 : std::accumulate (v.begin (), v.end (), 0.0) / double (v.size ());
}

} // namespace

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
  const std::size_t n = graph.numVertices ();
  std::vector<double> root_degree (n, 0.0);
  for (std::size_t i = 0; i < n; ++i)
    for (std::uint64_t e = graph.row_ptr[i]; e < graph.row_ptr[i + 1]; ++e)
      root_degree[i] += std::sqrt (double (graph.weight[e]));
  const double mean_root = meanOf (root_degree);
  if (!(mean_root > 0.0) || !(graph.spacing > 0.0) || !(noise > 0.0))
    return 0.0;
  return kTotalVariationC * noise / mean_root;
}

} // namespace core
} // namespace pcl_graph_denoise

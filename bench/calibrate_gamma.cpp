/*
 * pcl_graph_denoise: graph-signal-processing point cloud denoising for PCL.
 * SPDX-License-Identifier: BSD-3-Clause
 *
 * How the constants of the data-derived gamma (core/default_gamma.cpp) were chosen:
 * noisy planes, spheres and cubes (20k and 100k points, noise 0.5%, 1% and 2% of the
 * size), the mean distance to the true surface for candidate rules, and their
 * geometric mean over the spheres and cubes (planes are shown, not scored: on a plane
 * more smoothing is always better).
 *
 *   calibrate_gamma
 *
 * Tikhonov candidates: gamma x mean degree = A r^p with r = noise / spacing, the noise
 * estimated by core::estimateNoiseLevel. TV candidates: gamma = B noise / mean_i sum_j
 * sqrt(w_ij). The defaults are Tikhonov A = 20, p = 1.5 and TV B = 10 (B = 15..20 is
 * about 1% better on average, but B = 10 keeps edges sharper than Tikhonov; see the
 * edge tests in test/test_smoothing.cpp).
 */
#include <pcl_graph_denoise/core/graph.h>
#include <pcl_graph_denoise/core/noise_level.h>
#include <pcl_graph_denoise/core/operators.h>
#include <pcl_graph_denoise/core/solvers.h>

#include "synthetic.h"

#include <cmath>
#include <cstdio>
#include <functional>
#include <vector>

using namespace pcl_graph_denoise;
using namespace pcl_graph_denoise::core;

int
main ()
{
  std::setvbuf (stdout, nullptr, _IOLBF, 0);  // progress shows as it comes
  struct TikhonovRule
  {
    double a, p;
  };
  const std::vector<TikhonovRule> tikhonov = {{8, 1}, {12, 1}, {18, 1}, {20, 1.5}, {30, 1.5}, {40, 2}};
  const std::vector<double> tv = {10, 15, 20, 25, 30, 40};
  const char *names[] = {"plane", "sphere", "cube"};
  std::vector<double> log_t (tikhonov.size (), 0.0), log_v (tv.size (), 0.0);
  int scored = 0;

  std::printf ("Tikhonov columns (A, p):");
  for (const auto &r : tikhonov)
    std::printf (" (%g, %g)", r.a, r.p);
  std::printf ("\nTV columns B:");
  for (double b : tv)
    std::printf (" %g", b);
  std::printf ("\n");
  for (int shape = 0; shape < 3; ++shape)
    for (std::size_t n : {20000, 100000})
      for (double noise : {0.005, 0.01, 0.02})
      {
        const synthetic::Cloud cloud = shape == 0   ? synthetic::noisyPlane (n, noise, 5)
                                       : shape == 1 ? synthetic::noisySphere (n, 1.0, noise, 5)
                                                    : synthetic::noisyCube (n, noise, 5);
        const synthetic::SurfaceDistance distance = shape == 0   ? synthetic::distanceToPlane
                                                    : shape == 1 ? synthetic::distanceToUnitSphere
                                                                 : synthetic::distanceToCube;
        PointMatrix points (cloud.size (), 3);
        for (std::size_t i = 0; i < cloud.size (); ++i)
          points.row (i) = cloud[i].getVector3fMap ().transpose ();
        const PointGraph graph = buildKnnGraph (points);
        Signal3 f (n, 3);
        for (std::size_t v = 0; v < n; ++v)
          f.row (v) = points.row (graph.order[v]).cast<double> ();
        const double sigma = estimateNoiseLevel (graph, f);
        const double r = sigma / graph.spacing;
        const auto error = [&] (const Signal3 &x) {
          double sum = 0.0;
          for (Eigen::Index i = 0; i < x.rows (); ++i)
            sum += distance (x.row (i).transpose ());
          return sum / x.rows ();
        };
        double degree = 0.0, root = 0.0;
        for (std::size_t i = 0; i < n; ++i)
          for (auto e = graph.row_ptr[i]; e < graph.row_ptr[i + 1]; ++e)
            degree += graph.weight[e], root += std::sqrt (graph.weight[e]);
        degree /= n;
        root /= n;
        std::printf ("%-6s %6zu noise %.3f estimated %.4f r %.2f input %.5f | Tikhonov", names[shape],
                     n, noise, sigma, r, error (f));
        for (std::size_t c = 0; c < tikhonov.size (); ++c)
        {
          const double e = error (solveTikhonov (graph, f, tikhonov[c].a * std::pow (r, tikhonov[c].p) / degree));
          std::printf (" %.5f", e);
          if (shape > 0)
            log_t[c] += std::log (e);
        }
        std::printf (" | TV");
        for (std::size_t c = 0; c < tv.size (); ++c)
        {
          const double e = error (solveTotalVariation (graph, f, tv[c] * sigma / root));
          std::printf (" %.5f", e);
          if (shape > 0)
            log_v[c] += std::log (e);
        }
        std::printf ("\n");
        std::fflush (stdout);
        scored += shape > 0;
      }
  std::printf ("geometric mean over spheres and cubes, Tikhonov:");
  for (double s : log_t)
    std::printf (" %.6f", std::exp (s / scored));
  std::printf ("\ngeometric mean over spheres and cubes, TV:");
  for (double s : log_v)
    std::printf (" %.6f", std::exp (s / scored));
  std::printf ("\n");
  return 0;
}

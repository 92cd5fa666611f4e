/*
 * pcl_graph_denoise: graph-signal-processing point cloud denoising for PCL.
 * SPDX-License-Identifier: BSD-3-Clause
 *
 * How the constants of the data-derived gamma (core/default_gamma.cpp) are chosen, for
 * the filters as they run by default (normal displacement and shrinkage correction on).
 * Calibration set, kept apart from the evaluation's PU-GAN meshes: the CAD benchmark's
 * block, joint, part-Lp and casting, the Stanford dragon and decimated bunny (each
 * normalised to the unit sphere, sampled uniformly), a sphere and a cube; 10,000, 20,000
 * and 50,000 points; Gaussian noise 0.5%, 1%, 2% and 3%. Error: the protocol's point-to-mesh
 * distance (squared, both ways) for the meshes, the mean distance to the surface for the
 * sphere and the cube.
 *
 *   calibrate_gamma [--data DIR] [--only NAME,NAME] [--sizes N,N] [--two-ring] [--no-risk]
 *                   [--no-twicing] [--default-only | --multiples M,M]
 *   calibrate_gamma --noise-table
 *
 * --only: the shapes whose names contain one of the names; --sizes: of 10000, 20000, 50000
 * (the seeds stay those of the full run); --two-ring: the filters with
 * setAdaptiveSupport (false); --no-twicing: with setShrinkageCorrection (false); --no-risk:
 * without the risk estimate's runs (its figures then read nan); --default-only: no sweep,
 * each cloud at the default gamma only, and the set's geometric mean error per filter (to
 * compare two builds or settings); --multiples: the sweep over these multiples only (1
 * among them), with the set's geometric mean error at each.
 *
 * For every cloud, both filters run at multiples m (1/4 to 16, steps of sqrt 2) of the
 * current default gamma (a "raw" line per cloud and filter: filter, shape, points, true
 * noise, estimated noise, spacing, detail length over spacing as the detail term reads it,
 * then the errors of the sweep); the best m is fitted as log m = a + b log r with
 * r = estimated noise / spacing (the quantity the rules scale with), and the fitted rule
 * is run to report, over the set, the geometric mean of its error over the best of the
 * sweep (1 = always the best) next to the current rule's and to
 * GammaSelection::RISK_ESTIMATE's (its chosen multiple and error over the best in each
 * cloud's line).
 */
#include <pcl_graph_denoise/core/noise_level.h>
#include <pcl_graph_denoise/graph_tikhonov_smoothing.h>
#include <pcl_graph_denoise/graph_tv_smoothing.h>

#include "mesh_metrics.h"
#include "synthetic.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <functional>
#include <sstream>
#include <string>
#include <vector>

using namespace pcl_graph_denoise;
using namespace pcl_graph_denoise::evaluation;

namespace {

struct Sample
{
  double r = 0.0;                 // estimated noise / spacing
  std::vector<double> error;      // per multiple
  double best = 0.0, best_m = 0.0;
  double gamma = 0.0;             // the current default gamma
  double noise = 0.0, spacing = 0.0;  // estimated noise, spacing (sigma * sqrt 2)
  double detail = 0.0;            // detail length over spacing, 1 / (curvature * spacing)
  double risk_error = 0.0, risk_m = 0.0;  // GammaSelection::RISK_ESTIMATE: error, multiple
};

// 1/4 to 16 in steps of sqrt 2; the default (1) is multiples[default_index]
// (--default-only: the default alone).
std::vector<double> multiples = {0.25, 0.354, 0.5, 0.707, 1.0, 1.414, 2.0,
                                 2.828, 4.0, 5.657, 8.0, 11.31, 16.0};
std::size_t default_index = 4;

bool adaptive_support = true;   // not --two-ring
bool twicing = true;            // not --no-twicing
bool with_risk = true;          // not --no-risk

/** core::estimateNoise on `cloud` over the default k-NN graph, as the filters read it. */
core::NoiseEstimate
estimateOn (const Cloud &cloud)
{
  core::PointMatrix points (static_cast<Eigen::Index> (cloud.size ()), 3);
  for (std::size_t i = 0; i < cloud.size (); ++i)
    points.row (static_cast<Eigen::Index> (i)) = cloud[i].getVector3fMap ().transpose ();
  const core::PointGraph graph = core::buildKnnGraph (points);
  core::Signal3 f (points.rows (), 3);
  for (Eigen::Index v = 0; v < points.rows (); ++v)
    f.row (v) = points.row (graph.order[static_cast<std::size_t> (v)]).cast<double> ();
  return core::estimateNoise (graph, f);
}

/** The detail length 1 / NoiseEstimate::curvature that core::detailGammaFactor reads on
 *  `cloud`; 0 when not measured. */
double
detailLength (const Cloud &cloud)
{
  const double curvature = estimateOn (cloud).curvature;
  return curvature > 0.0 ? 1.0 / curvature : 0.0;
}

/** A filter on `cloud` with the run's settings (--two-ring, --no-twicing). */
template <typename Filter>
void
configure (Filter &filter, const Cloud::Ptr &cloud)
{
  filter.setInputCloud (cloud);
  filter.setAdaptiveSupport (adaptive_support);
  filter.setShrinkageCorrection (twicing);
}

template <typename Filter>
Sample
sweep (const Cloud::Ptr &cloud, const std::function<double (const Cloud &)> &error)
{
  Filter filter;
  configure (filter, cloud);
  Cloud out;
  filter.filter (out);
  const double at_default = error (out);  // the run at m = 1
  Sample s;
  s.gamma = filter.getUsedGamma ();
  s.noise = filter.getEstimatedNoise ();
  s.spacing = std::sqrt (2.0) * filter.getUsedSigma ();  // sigma = spacing / sqrt 2
  s.r = s.noise / s.spacing;
  s.detail = detailLength (*cloud) / s.spacing;
  s.best = std::numeric_limits<double>::infinity ();
  for (double m : multiples)
  {
    if (m == 1.0)
      s.error.push_back (at_default);
    else
    {
      filter.setGamma (m * s.gamma);
      filter.filter (out);
      s.error.push_back (error (out));
    }
    if (s.error.back () < s.best)
      s.best = s.error.back (), s.best_m = m;
  }
  s.risk_error = s.risk_m = std::numeric_limits<double>::quiet_NaN ();
  if (!with_risk)
    return s;
  filter.setAutomaticGamma ();
  filter.setGammaSelection (GammaSelection::RISK_ESTIMATE);
  filter.filter (out);
  s.risk_error = error (out);
  s.risk_m = filter.getUsedGamma () / s.gamma;
  return s;
}

/** Least squares fit of log(best m) = a + b log r. */
std::pair<double, double>
fit (const std::vector<Sample> &samples)
{
  double sx = 0, sy = 0, sxx = 0, sxy = 0;
  const double n = double (samples.size ());
  for (const auto &s : samples)
  {
    const double x = std::log (s.r), y = std::log (s.best_m);
    sx += x, sy += y, sxx += x * x, sxy += x * y;
  }
  const double b = (n * sxy - sx * sy) / (n * sxx - sx * sx);
  return {(sy - b * sx) / n, b};
}

/** The table behind core::estimateNoise: on noisy planes of 160,000 points (three seeds,
 *  the default k-NN graph), the median two-ring residual over the spacing, against the
 *  noise over the spacing. */
void
printNoiseTable ()
{
  const std::size_t n = 160000;
  const double spacing = 2.0 / std::sqrt (double (n));  // the plane is 2 x 2
  std::printf ("{noise / spacing, median residual / spacing}\n");
  for (double r : {0.1, 0.25, 0.5, 0.75, 1.0, 1.25, 1.5, 2.0, 2.5, 3.0, 4.0, 5.0, 6.0, 8.0, 10.0, 12.0, 16.0})
  {
    double residual = 0.0, measured = 0.0, level = 0.0;
    for (std::uint64_t seed : {1, 2, 3})
    {
      const core::NoiseEstimate e = estimateOn (synthetic::noisyPlane (n, r * spacing, seed));
      residual += e.two_ring / spacing / 3.0;
      measured += e.spacing / spacing / 3.0;
      level += e.level / (r * spacing) / 3.0;
    }
    std::printf ("    {%.2f, %.4f},  // estimated spacing / true %.3f, level / true %.3f\n", r, residual,
                 measured, level);
  }
}

} // namespace

int
main (int argc, char **argv)
{
  std::setvbuf (stdout, nullptr, _IOLBF, 0);
  if (argc == 2 && !std::strcmp (argv[1], "--noise-table"))
  {
    printNoiseTable ();
    return 0;
  }
  std::string data = PGD_SHARED_DATA;
  std::string only;  // comma-separated substrings of the shape names to run
  std::string sizes = ",10000,20000,50000,";
  const char *usage = "usage: %s [--data DIR] [--only NAME,NAME] [--sizes N,N] [--two-ring] "
                      "[--no-risk] [--no-twicing] [--default-only | --multiples M,M] | "
                      "--noise-table\n";
  for (int a = 1; a < argc; ++a)
  {
    const bool has_value = a + 1 < argc;
    if (!std::strcmp (argv[a], "--two-ring"))
      adaptive_support = false;
    else if (!std::strcmp (argv[a], "--no-risk"))
      with_risk = false;
    else if (!std::strcmp (argv[a], "--no-twicing"))
      twicing = false;
    else if (!std::strcmp (argv[a], "--default-only"))
      multiples = {1.0}, default_index = 0;
    else if (has_value && !std::strcmp (argv[a], "--multiples"))
    {
      multiples.clear ();
      std::stringstream list (argv[++a]);
      for (std::string item; std::getline (list, item, ',');)
        multiples.push_back (std::atof (item.c_str ()));
      const auto one = std::find (multiples.begin (), multiples.end (), 1.0);
      if (one == multiples.end ())
      {
        std::fprintf (stderr, "error: --multiples must include 1\n");
        return 2;
      }
      default_index = static_cast<std::size_t> (one - multiples.begin ());
    }
    else if (has_value && !std::strcmp (argv[a], "--data"))
      data = argv[++a];
    else if (has_value && !std::strcmp (argv[a], "--only"))
      only = std::string (",") + argv[++a] + ",";
    else if (has_value && !std::strcmp (argv[a], "--sizes"))
      sizes = std::string (",") + argv[++a] + ",";
    else
    {
      std::fprintf (stderr, usage, argv[0]);
      return 2;
    }
  }
  const auto wanted = [&] (const std::string &name) {
    if (only.empty ())
      return true;
    std::size_t start = 1;
    for (std::size_t comma; (comma = only.find (',', start)) != std::string::npos; start = comma + 1)
      if (comma > start && name.find (only.substr (start, comma - start)) != std::string::npos)
        return true;
    return false;
  };
  struct Shape
  {
    std::string name;
    std::function<Cloud (std::size_t, double, std::uint64_t)> sample;
    std::function<double (const Cloud &)> error;
  };
  std::vector<Shape> shapes;
  std::vector<std::unique_ptr<MeshDistance>> distances;
  for (const char *file : {"cad_denoise_benchmark/block.obj", "cad_denoise_benchmark/joint.obj",
                           "cad_denoise_benchmark/partLp.obj", "cad_denoise_benchmark/casting.obj",
                           "stanford/dragon_vrip_res3.ply", "stanford/bun_zipper_res2.ply"})
  {
    TriangleMesh mesh;
    std::string error;
    if (!loadMesh (data + "/meshes/" + file, mesh, error))
    {
      std::fprintf (stderr, "error: %s\n", error.c_str ());
      return 2;
    }
    transform (unitSphereNormalisation (mesh), mesh);
    distances.emplace_back (new MeshDistance (mesh));
    const MeshDistance *d = distances.back ().get ();
    shapes.push_back ({file, [d] (std::size_t n, double noise, std::uint64_t seed) {
                         return addGaussianNoise (sampleSurface (d->mesh (), n, seed), noise, seed + 1);
                       },
                       [d] (const Cloud &c) { return pointToMeshDistance (c, *d); }});
  }
  shapes.push_back ({"sphere", [] (std::size_t n, double noise, std::uint64_t seed) {
                       return synthetic::noisySphere (n, 1.0, noise, seed);
                     },
                     [] (const Cloud &c) { return synthetic::meanDistance (c, synthetic::distanceToUnitSphere); }});
  shapes.push_back ({"cube", [] (std::size_t n, double noise, std::uint64_t seed) {
                       return synthetic::noisyCube (n, 0.577 * noise, seed);  // unit-sphere scale
                     },
                     [] (const Cloud &c) { return synthetic::meanDistance (c, synthetic::distanceToCube); }});

  std::vector<Sample> tikhonov, tv;
  std::vector<Cloud::Ptr> clouds;
  std::vector<const Shape *> of;
  std::uint64_t seed = 7000;
  for (const auto &shape : shapes)
    for (std::size_t n : {10000, 20000, 50000})
      for (double noise : {0.005, 0.01, 0.02, 0.03})
      {
        seed += 2;  // the same seeds whichever shapes and sizes run
        if (!wanted (shape.name) || sizes.find ("," + std::to_string (n) + ",") == std::string::npos)
          continue;
        clouds.emplace_back (new Cloud (shape.sample (n, noise, seed)));
        of.push_back (&shape);
        tikhonov.push_back (sweep<GraphTikhonovSmoothing<pcl::PointXYZ>> (clouds.back (), shape.error));
        tv.push_back (sweep<GraphTVSmoothing<pcl::PointXYZ>> (clouds.back (), shape.error));
        std::printf ("%-32s %5zu noise %.3f r %.3f | best multiple: Tikhonov %g (%.3gx the default's "
                     "error; risk estimate %.3g: %.3gx), TV %g (%.3gx; risk estimate %.3g: %.3gx)\n",
                     shape.name.c_str (), n, noise, tikhonov.back ().r, tikhonov.back ().best_m,
                     tikhonov.back ().error[default_index] / tikhonov.back ().best, tikhonov.back ().risk_m,
                     tikhonov.back ().risk_error / tikhonov.back ().best, tv.back ().best_m,
                     tv.back ().error[default_index] / tv.back ().best, tv.back ().risk_m,
                     tv.back ().risk_error / tv.back ().best);
        for (const Sample *sample : {&tikhonov.back (), &tv.back ()})
        {
          std::printf ("raw %s %s %zu %g %g %g %g", sample == &tv.back () ? "tv" : "tikhonov",
                       shape.name.c_str (), n, noise, sample->noise, sample->spacing, sample->detail);
          for (double e : sample->error)
            std::printf (" %g", e);
          std::printf ("\n");
        }
      }

  if (multiples.size () == 1)
  {
    // --default-only: the set's error at the default gamma, to compare builds.
    for (int which = 0; which < 2; ++which)
    {
      const auto &samples = which == 0 ? tikhonov : tv;
      double log_error = 0.0;
      for (const Sample &sample : samples)
        log_error += std::log (sample.error[0]);
      std::printf ("%s: default gamma, geometric mean error over %zu clouds %.6g\n",
                   which == 0 ? "Tikhonov" : "TV", samples.size (),
                   std::exp (log_error / double (samples.size ())));
    }
    return 0;
  }
  // The set's geometric mean error at each multiple (a constant change of the rule).
  for (int which = 0; which < 2; ++which)
  {
    const auto &samples = which == 0 ? tikhonov : tv;
    std::printf ("%s: geometric mean error over %zu clouds at each multiple:", which == 0 ? "Tikhonov" : "TV",
                 samples.size ());
    for (std::size_t k = 0; k < multiples.size (); ++k)
    {
      double log_error = 0.0;
      for (const Sample &sample : samples)
        log_error += std::log (sample.error[k]);
      std::printf (" %g %.6g", multiples[k], std::exp (log_error / double (samples.size ())));
    }
    std::printf ("\n");
  }
  for (int which = 0; which < 2; ++which)
  {
    const auto &samples = which == 0 ? tikhonov : tv;
    const auto [a, b] = fit (samples);
    double log_current = 0.0, log_fitted = 0.0, log_risk = 0.0;
    for (std::size_t i = 0; i < samples.size (); ++i)
    {
      const double m = std::exp (a) * std::pow (samples[i].r, b);
      Cloud out;
      const auto run = [&] (auto &&f) {
        configure (f, clouds[i]);
        f.setGamma (m * samples[i].gamma);
        f.filter (out);
      };
      if (which == 0)
        run (GraphTikhonovSmoothing<pcl::PointXYZ> ());
      else
        run (GraphTVSmoothing<pcl::PointXYZ> ());
      log_current += std::log (samples[i].error[default_index] / samples[i].best);
      log_risk += std::log (samples[i].risk_error / samples[i].best);
      log_fitted += std::log (of[i]->error (out) / samples[i].best);
    }
    std::printf ("%s: best multiple ~ %.3g r^%.3f; error over the best of the sweep, geometric "
                 "mean: current rule %.3f, fitted %.3f, risk estimate %.3f\n",
                 which == 0 ? "Tikhonov" : "TV", std::exp (a), b, std::exp (log_current / samples.size ()),
                 std::exp (log_fitted / samples.size ()), std::exp (log_risk / samples.size ()));
  }
  return 0;
}

/*
 * pcl_graph_denoise: graph-signal-processing point cloud denoising for PCL.
 * SPDX-License-Identifier: BSD-3-Clause
 */
#pragma once

/* The evaluation suite (docs/evaluation.md): one function per section, each writing
 * its tables under the output directory and returning non-zero in quick mode when a
 * claim that the report states no longer holds. */

#include <pcl_graph_denoise/graph_smoothing.h>

#include <pcl/point_cloud.h>
#include <pcl/point_types.h>

#include <functional>
#include <ostream>
#include <string>
#include <vector>

namespace pcl_graph_denoise {
namespace evaluation {

struct Options
{
  bool quick = false;
  std::string out = ".";   ///< where the tables (.md, .dat) and files are written
  std::string data;        ///< the shared data folder (../shared/data)
  std::vector<std::size_t> sizes;  ///< pugan: cloud sizes (empty = the section's own)
  bool wlop = false;               ///< pugan: also run WLOP (slow: ~16 s per 10,000 points)
  bool risk = true;                ///< pugan, bunny: also ours with the risk-estimate gamma
  bool adaptive_support = true;    ///< pugan, bunny: false = ours with setAdaptiveSupport (false)
};

int
figure3 (const Options &options);
int
pugan (const Options &options);
int
bunny (const Options &options);
int
outliers (const Options &options);
int
sequences (const Options &options);

using Cloud = pcl::PointCloud<pcl::PointXYZ>;

/** One denoiser's result on one cloud: for the methods with a swept parameter, the
 *  setting with the lowest error. */
struct MethodResult
{
  std::string method;   ///< e.g. "TV (defaults)", "MLS (best radius)"
  std::string setting;  ///< the chosen setting, empty for defaults
  double error = 0.0;   ///< by the caller's measure
  double seconds = 0.0; ///< the chosen setting's time
  Cloud output;
};

struct MethodOptions
{
  bool wlop = true;                                  ///< WLOP is slow: optional
  bool risk_gamma = true;  ///< ours with GammaSelection::RISK_ESTIMATE (about 20 runs each)
  bool adaptive_support = true;   ///< false: ours with setAdaptiveSupport (false)
  std::vector<unsigned> bilateral_k = {30, 60, 120}; ///< the bilateral filter's sweep
};

/** The methods' settings a section's options ask for: --no-risk, --two-ring, --wlop, and
 *  --quick's smaller sweeps (one bilateral k, no risk estimate, no WLOP). */
MethodOptions
methodOptions (const Options &options);

/** The line a table of ours run with --two-ring starts with (empty otherwise): the method
 *  names stay the defaults'. */
std::string
runNote (const Options &options);

/** Runs every method of the comparison on `noisy`: the input itself, ours (Tikhonov and
 *  TV with defaults, and at the best gamma of a sweep over 1/4x to 4x the default), and
 *  the peers at the best setting of a sweep each: pcl::MovingLeastSquares (radius 1 to 3
 *  times the mean distance to the 20th neighbour), CGAL jet (k = 18, 36, 72), bilateral
 *  (3 passes, sharpness 25 degrees) and WLOP (CGAL defaults). "Best" is the lowest
 *  `error`. In the order of `methodNames ()`. */
std::vector<MethodResult>
runMethods (const Cloud::Ptr &noisy, const std::function<double (const Cloud &)> &error,
            const MethodOptions &options);

/** A smoother of ours with its data-derived gamma, and at the best of `factors` times
 *  that gamma (the default itself counting as the factor 1): the results named
 *  "<name> (defaults)" and "<name> (best γ)". The filter's other settings are the
 *  caller's; `rule_gamma`, when given, receives the data-derived gamma. */
std::pair<MethodResult, MethodResult>
defaultAndBestGamma (GraphSmoothing<pcl::PointXYZ> &filter, const std::string &name, const Cloud::Ptr &noisy,
                     const std::function<double (const Cloud &)> &error, const std::vector<double> &factors,
                     double *rule_gamma = nullptr);

/** The methods runMethods reports, in order; the peers come from `firstPeer ()` on. */
const std::vector<std::string> &
methodNames ();
std::size_t
firstPeer ();

/** A claim of the report checked on the numbers: `asserted` marks those the report
 *  states as holding; quick mode fails when one of them does not. */
struct Finding
{
  std::string text;
  bool holds, asserted;
};

/** Writes the findings as a list to `md` and stdout; returns the number of asserted
 *  findings that do not hold. */
int
reportFindings (const std::vector<Finding> &findings, std::ostream &md);

} // namespace evaluation
} // namespace pcl_graph_denoise

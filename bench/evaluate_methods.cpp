/*
 * pcl_graph_denoise: graph-signal-processing point cloud denoising for PCL.
 * SPDX-License-Identifier: BSD-3-Clause
 *
 * The methods every section of the evaluation compares, in one place.
 */
#include "evaluate.h"

#include <pcl_graph_denoise/graph_tikhonov_smoothing.h>
#include <pcl_graph_denoise/graph_tv_smoothing.h>

#include "peers.h"
#include "timing.h"

#include <cmath>
#include <limits>

namespace pcl_graph_denoise {
namespace evaluation {

namespace {

template <typename Setting>
MethodResult
bestOf (const std::string &method, const std::vector<Setting> &settings,
        const std::function<Cloud (const Setting &)> &run,
        const std::function<std::string (const Setting &)> &label,
        const std::function<double (const Cloud &)> &error)
{
  MethodResult best;
  best.method = method;
  best.error = std::numeric_limits<double>::infinity ();
  for (const auto &setting : settings)
  {
    Cloud out;
    const double t = seconds ([&] { out = run (setting); });
    const double e = error (out);
    if (e < best.error)
    {
      best.setting = label (setting);
      best.error = e;
      best.seconds = t;
      best.output = std::move (out);
    }
  }
  return best;
}

/** A row for a method that was not run (its error and time NaN). */
MethodResult
notRun (const std::string &method)
{
  MethodResult result;
  result.method = method;
  result.setting = "not run";
  result.error = result.seconds = std::nan ("");
  return result;
}

} // namespace

std::pair<MethodResult, MethodResult>
defaultAndBestGamma (GraphSmoothing<pcl::PointXYZ> &filter, const std::string &name, const Cloud::Ptr &noisy,
                     const std::function<double (const Cloud &)> &error, const std::vector<double> &factors,
                     double *rule_gamma)
{
  filter.setAutomaticGamma ();
  filter.setInputCloud (noisy);
  MethodResult by_default;
  by_default.method = name + " (defaults)";
  by_default.seconds = seconds ([&] { filter.filter (by_default.output); });
  by_default.error = error (by_default.output);
  const double gamma = filter.getUsedGamma ();
  if (rule_gamma)
    *rule_gamma = gamma;
  MethodResult best = bestOf<double> (
      name + " (best γ)", factors,
      [&] (const double &f) {
        filter.setGamma (f * gamma);
        Cloud out;
        filter.filter (out);
        return out;
      },
      [] (const double &f) {
        char label[16];
        std::snprintf (label, sizeof (label), "%gx", f);
        return std::string (label);
      },
      error);
  if (!(best.error < by_default.error))  // the default is one of the candidates
  {
    best = by_default;
    best.method = name + " (best γ)";
    best.setting = "1x";
  }
  return {by_default, best};
}

const std::vector<std::string> &
methodNames ()
{
  static const std::vector<std::string> names = {
      "noisy input",       "Tikhonov (defaults)", "Tikhonov (best γ)",  "TV (defaults)",
      "TV (best γ)",       "Tikhonov (risk γ)",   "TV (risk γ)",        "MLS (best radius)",
      "jet (best k)",      "bilateral (best k)",  "WLOP"};
  return names;
}

std::size_t
firstPeer ()
{
  return 7;
}

MethodOptions
methodOptions (const Options &options)
{
  MethodOptions m;
  m.wlop = options.wlop && !options.quick;
  m.risk_gamma = options.risk && !options.quick;
  m.adaptive_support = options.adaptive_support;
  if (options.quick)
    m.bilateral_k = {60};
  return m;
}

std::string
runNote (const Options &options)
{
  return options.adaptive_support ? "" : "Ours with `setAdaptiveSupport (false)` (`--two-ring`).\n\n";
}

std::vector<MethodResult>
runMethods (const Cloud::Ptr &noisy, const std::function<double (const Cloud &)> &error,
            const MethodOptions &options)
{
  std::vector<MethodResult> results;
  MethodResult input;
  input.method = "noisy input";
  input.output = *noisy;
  input.error = error (input.output);
  results.push_back (std::move (input));
  const std::vector<double> factors = {0.25, 0.5, 2.0, 4.0};
  GraphTikhonovSmoothing<pcl::PointXYZ> tikhonov;
  GraphTVSmoothing<pcl::PointXYZ> tv;
  tikhonov.setAdaptiveSupport (options.adaptive_support);
  tv.setAdaptiveSupport (options.adaptive_support);
  const std::pair<GraphSmoothing<pcl::PointXYZ> *, const char *> ours[] = {{&tikhonov, "Tikhonov"},
                                                                           {&tv, "TV"}};
  std::vector<MethodResult> by_risk;
  for (const auto &[filter, name] : ours)
  {
    double rule_gamma = 0.0;
    auto r = defaultAndBestGamma (*filter, name, noisy, error, factors, &rule_gamma);
    results.push_back (std::move (r.first));
    results.push_back (std::move (r.second));
    // GammaSelection::RISK_ESTIMATE, with the multiple of the rule's gamma it chose.
    const std::string method = std::string (name) + " (risk γ)";
    if (!options.risk_gamma)
    {
      by_risk.push_back (notRun (method));
      continue;
    }
    MethodResult risk;
    risk.method = method;
    filter->setAutomaticGamma ();
    filter->setGammaSelection (GammaSelection::RISK_ESTIMATE);
    risk.seconds = seconds ([&] { filter->filter (risk.output); });
    risk.error = error (risk.output);
    char label[32];
    std::snprintf (label, sizeof (label), "%.3gx", rule_gamma > 0.0 ? filter->getUsedGamma () / rule_gamma : 0.0);
    risk.setting = label;
    filter->setGammaSelection (GammaSelection::RULE);
    by_risk.push_back (std::move (risk));
  }
  for (auto &r : by_risk)
    results.push_back (std::move (r));

  const double d20 = peers::meanKthNeighbourDistance (*noisy, 20);
  const auto label_k = [] (const unsigned &k) { return "k=" + std::to_string (k); };
  results.push_back (bestOf<double> (
      "MLS (best radius)", {1.0, 1.5, 2.0, 3.0},
      [&] (const double &f) { return peers::movingLeastSquares (*noisy, f * d20); },
      [] (const double &f) {
        char label[16];
        std::snprintf (label, sizeof (label), "r=%gd20", f);
        return std::string (label);
      },
      error));
  results.push_back (bestOf<unsigned> (
      "jet (best k)", {18, 36, 72}, [&] (const unsigned &k) { return peers::jetSmooth (*noisy, k); },
      label_k, error));
  results.push_back (bestOf<unsigned> (
      "bilateral (best k)", options.bilateral_k,
      [&] (const unsigned &k) { return peers::bilateralSmooth (*noisy, k, 25.0, 3); }, label_k, error));
  if (options.wlop)
  {
    MethodResult wlop;
    wlop.method = "WLOP";
    wlop.seconds = seconds ([&] { wlop.output = peers::wlop (*noisy, 0.0); });
    wlop.error = error (wlop.output);
    results.push_back (std::move (wlop));
  }
  else
    results.push_back (notRun ("WLOP"));
  return results;
}

} // namespace evaluation
} // namespace pcl_graph_denoise

/*
 * pcl_graph_denoise: graph-signal-processing point cloud denoising for PCL.
 * SPDX-License-Identifier: BSD-3-Clause
 *
 * The command-line tool: reads a .pcd or .ply file with all its fields, runs a chain of
 * the library's filters on its x, y, z (outlier removal, Tikhonov and TV smoothing, in
 * the order given) and writes the result with every other field untouched; with a
 * -temporal step, on the frames of a sequence (several inputs, one output folder).
 *
 *   pcl_graph_denoise input.{pcd,ply} output.{pcd,ply} [options] [step [step options]]...
 *   pcl_graph_denoise frame.{pcd,ply}... folder [options] [step [step options]]... -temporal
 *
 * See usage() in options.cpp (or run with -h) for the options.
 */
#include "cloud_fields.h"
#include "cloud_io.h"
#include "options.h"
#include "stderr_capture.h"

#include <pcl_graph_denoise/graph_degree_outlier_removal.h>
#include <pcl_graph_denoise/graph_sequence_smoothing.h>
#include <pcl_graph_denoise/graph_tikhonov_smoothing.h>
#include <pcl_graph_denoise/graph_tv_smoothing.h>

#include <pcl/common/io.h>
#include <pcl/console/print.h>
#include <pcl/console/time.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <exception>
#include <functional>
#include <limits>
#include <memory>
#include <new>
#include <string>
#include <vector>

using namespace pcl_graph_denoise::tools;
using pcl::console::print_highlight;
using pcl::console::print_info;
using pcl::console::print_value;

namespace {

using Cloud = pcl::PointCloud<pcl::PointXYZ>;

const char *const program = "pcl_graph_denoise";

/** The report of what the tool does, on stderr; silent with -q. */
bool quiet = false;

template <typename... Args>
void
highlight (const char *format, Args... args)
{
  if (!quiet)
    print_highlight (stderr, format, args...);
}

template <typename... Args>
void
info (const char *format, Args... args)
{
  if (!quiet)
    print_info (stderr, format, args...);
}

template <typename... Args>
void
value (const char *format, Args... args)
{
  if (!quiet)
    print_value (stderr, format, args...);
}

/** "step 2/3 (-tv)", for messages. */
std::string
stepName (const Options &options, std::size_t s)
{
  return "step " + std::to_string (s + 1) + "/" + std::to_string (options.steps.size ()) + " (" +
         stepOption (options.steps[s].kind) + ")";
}

/** The parameters set for a step, as given: "-gamma 0.01, -k 12". */
std::string
describeParameters (const Step &step)
{
  std::string text;
  for (const auto &[name, v] : step.parameters)
  {
    char number[64];
    std::snprintf (number, sizeof (number), "%g", v.number);
    text += (text.empty () ? "-" : ", -") + name + " " + (v.text.empty () ? number : v.text);
  }
  return text.empty () ? "none, the filter's defaults" : text;
}

/** The progress of a smoothing filter, written through the capture of its messages at
 *  once: each pass's graph, and the solver's iteration and residual at most every second.
 *  Nothing with -q. */
std::function<void (const pcl_graph_denoise::SmoothingProgress &)>
progressPrinter (const StderrCapture &capture)
{
  if (quiet)
    return {};
  using Clock = std::chrono::steady_clock;
  auto last = std::make_shared<Clock::time_point> (Clock::now ());
  return [&capture, last] (const pcl_graph_denoise::SmoothingProgress &event) {
    char line[160];
    const auto now = Clock::now ();
    if (event.stage == pcl_graph_denoise::SmoothingProgress::GRAPH_BUILT)
      std::snprintf (line, sizeof (line), "  pass %d: graph of %zu points, %zu edges\n", event.pass + 1,
                     event.vertices, event.edges);
    else if (now - *last >= std::chrono::seconds (1))
      std::snprintf (line, sizeof (line), "  pass %d: solver iteration %d, residual %.3g\n",
                     event.pass + 1, event.iterations, event.residual);
    else
      return;
    *last = now;
    capture.writeThrough (line);
  };
}

/** Runs `work` (a smoother's filter(), push() or flush()) with stderr captured, PCL's
 *  messages kept for after, and the smoother's progress written through at once; returns
 *  the captured text. */
template <typename Work>
std::string
runReporting (pcl_graph_denoise::GraphSmoothing<pcl::PointXYZ> &smoother, Work &&work)
{
  StderrCapture capture;
  smoother.setProgressCallback (progressPrinter (capture));
  work ();
  smoother.setProgressCallback ({});
  return capture.release ();
}

/** Passes on what a filter printed (warnings) once it is done. */
void
forward (const std::string &captured)
{
  if (!captured.empty ())
    std::fputs (captured.c_str (), stderr);
}

void
configure (pcl_graph_denoise::GraphDegreeOutlierRemoval<pcl::PointXYZ> &filter, const Step &step)
{
  for (const auto &[name, v] : step.parameters)
  {
    if (name == "radius")
      filter.setRadiusSearch (v.number);
    else if (name == "sigma")
      filter.setSigma (v.number);
    else if (name == "threshold_ratio")
      filter.setAutomaticThresholdRatio (v.number);
    else if (name == "degree_threshold")
      filter.setDegreeThreshold (v.number);
    else if (name == "outlier_fraction")
      filter.setOutlierFraction (v.number);
    else if (name == "residual_threshold")
      filter.setResidualThreshold (v.number);
    else if (name == "keep_sparse_surfaces")
      filter.setKeepSparseSurfaces (v.number != 0.0);
    else if (name == "threads")
      filter.setNumberOfThreads (static_cast<int> (v.number));
    else if (name == "memory_limit")
      filter.setMemoryLimit (megabytesToBytes (v.number));
  }
}

void
configure (pcl_graph_denoise::GraphSmoothing<pcl::PointXYZ> &filter, const Step &step)
{
  for (const auto &[name, v] : step.parameters)
  {
    if (name == "k")
      filter.setKSearch (static_cast<int> (v.number));
    else if (name == "sigma")
      filter.setSigma (v.number);
    else if (name == "gamma")
    {
      if (v.text == "auto" || v.text == "risk")
      {
        filter.setAutomaticGamma ();
        filter.setGammaSelection (v.text == "risk" ? pcl_graph_denoise::GammaSelection::RISK_ESTIMATE
                                                   : pcl_graph_denoise::GammaSelection::RULE);
      }
      else
        filter.setGamma (v.number);
    }
    else if (name == "graph_iterations")
      filter.setGraphIterations (static_cast<int> (v.number));
    else if (name == "normal_displacement")
      filter.setNormalDisplacement (v.number != 0.0);
    else if (name == "local_surface")
    {
      pcl_graph_denoise::LocalSurface surface = filter.getLocalSurface ();
      pcl_graph_denoise::tools::localSurfaceFromName (v.text, surface);  // checked when parsed
      filter.setLocalSurface (surface);
    }
    else if (name == "adaptive_support")
      filter.setAdaptiveSupport (v.number != 0.0);
    else if (name == "patch_cover")
      filter.setPatchCover (static_cast<int> (v.number));
    else if (name == "shrinkage_correction")
      filter.setShrinkageCorrection (v.number != 0.0);
    else if (name == "density_normalization")
      filter.setDensityNormalization (v.number != 0.0);
    else if (name == "tolerance")
      filter.setTolerance (v.number);
    else if (name == "max_iterations")
      filter.setMaximumIterations (static_cast<int> (v.number));
    else if (name == "threads")
      filter.setNumberOfThreads (static_cast<int> (v.number));
    else if (name == "memory_limit")
      filter.setMemoryLimit (megabytesToBytes (v.number));
  }
}

/** The parameters of a step that belong to one smoother: -solver (Tikhonov), -norm (TV). */
void
configureSolvers (const Step &step, pcl_graph_denoise::GraphTikhonovSmoothing<pcl::PointXYZ> &tikhonov,
                  pcl_graph_denoise::GraphTVSmoothing<pcl::PointXYZ> &tv)
{
  if (step.has ("solver"))
    tikhonov.setSolver (step.parameters.at ("solver").text == "cholmod"
                            ? pcl_graph_denoise::core::TikhonovSolver::CHOLMOD
                            : pcl_graph_denoise::core::TikhonovSolver::CONJUGATE_GRADIENT);
  if (step.has ("norm"))
    tv.setNorm (step.parameters.at ("norm").text == "anisotropic"
                    ? pcl_graph_denoise::core::TotalVariationNorm::ANISOTROPIC
                    : pcl_graph_denoise::core::TotalVariationNorm::ISOTROPIC);
}

/** Removes the outliers of `cloud` (whole points); the removed ones go to `removed`. */
void
removeOutliers (const Options &options, std::size_t s, const XyzFields &xyz,
                pcl::PCLPointCloud2 &cloud, pcl::PCLPointCloud2 &removed)
{
  const Step &step = options.steps[s];
  pcl_graph_denoise::GraphDegreeOutlierRemoval<pcl::PointXYZ> filter (true);
  configure (filter, step);
  const Cloud::Ptr input = xyz.extract (cloud);
  const std::size_t finite = countFinite (*input);
  filter.setInputCloud (input);
  pcl::Indices kept;
  std::string captured;
  {
    StderrCapture capture;
    filter.filter (kept);
    captured = capture.release ();
  }
  const pcl::Indices &gone = *filter.getRemovedIndices ();
  if (kept.size () + gone.size () != input->size ())
  {
    const std::string why = mainMessage (captured);
    throw Error (stepName (options, s) + " failed" + (why.empty () ? "" : ": " + why));
  }
  forward (captured);

  appendPoints (removed, selectPoints (cloud, gone));
  const bool keep_organized =
      step.has ("keep_organized") && step.parameters.at ("keep_organized").number != 0.0;
  if (keep_organized)
  {
    for (const auto index : gone)
      xyz.setNaN (cloud, static_cast<std::size_t> (index));
  }
  else
    cloud = selectPoints (cloud, kept);

  const char *rule = "";
  switch (filter.getThresholdRule ())
  {
  case pcl_graph_denoise::GraphDegreeOutlierRemoval<pcl::PointXYZ>::AUTOMATIC_THRESHOLD:
    rule = "threshold_ratio x first quartile";
    break;
  case pcl_graph_denoise::GraphDegreeOutlierRemoval<pcl::PointXYZ>::ABSOLUTE_THRESHOLD:
    rule = "degree_threshold";
    break;
  case pcl_graph_denoise::GraphDegreeOutlierRemoval<pcl::PointXYZ>::OUTLIER_FRACTION:
    rule = "outlier_fraction";
    break;
  }
  info ("  removed ");
  value ("%zu", gone.size ());
  info (" of ");
  value ("%zu", input->size ());
  info (" points (");
  value ("%zu", input->size () - finite);
  info (" with a non-finite x, y, z)%s -> ", keep_organized ? ", kept as NaN" : "");
  value ("%zu", std::size_t (cloud.width) * cloud.height);
  info (" points\n  used: radius ");
  value ("%g", filter.getUsedRadius ());
  info (", sigma ");
  value ("%g", filter.getUsedSigma ());
  info (", degree threshold ");
  value ("%g", filter.getUsedDegreeThreshold ());
  info (" (%s)", rule);
  if (filter.getUsedResidualScale () > 0.0)
  {
    info (", residual test ");
    value ("%g", filter.getResidualThreshold ());
    info (" x noise scale ");
    value ("%g", filter.getUsedResidualScale ());
  }
  info ("\n");
}

/** Smooths x, y, z of `cloud` with a GraphTikhonovSmoothing or GraphTVSmoothing. */
void
smooth (const Options &options, std::size_t s, const XyzFields &xyz, pcl::PCLPointCloud2 &cloud)
{
  const Step &step = options.steps[s];
  pcl_graph_denoise::GraphTikhonovSmoothing<pcl::PointXYZ> tikhonov;
  pcl_graph_denoise::GraphTVSmoothing<pcl::PointXYZ> tv;
  pcl_graph_denoise::GraphSmoothing<pcl::PointXYZ> &filter =
      step.kind == StepKind::TIKHONOV
          ? static_cast<pcl_graph_denoise::GraphSmoothing<pcl::PointXYZ> &> (tikhonov)
          : tv;
  configure (filter, step);
  configureSolvers (step, tikhonov, tv);

  const Cloud::Ptr input = xyz.extract (cloud);
  const std::size_t finite = countFinite (*input);
  if (finite == 0)
    throw Error (stepName (options, s) + ": no point with a finite x, y, z is left to smooth");
  filter.setInputCloud (input);
  Cloud output;
  const std::string captured = runReporting (filter, [&] { filter.filter (output); });
  if (output.size () != input->size ())
  {
    const std::string why = mainMessage (captured);
    throw Error (stepName (options, s) + " failed" + (why.empty () ? "" : ": " + why));
  }
  forward (captured);
  const std::size_t moved = xyz.writeBack (cloud, *input, output);

  const auto &report = filter.getSolverReport ();
  info ("  ");
  value ("%zu", input->size ());
  info (" points (");
  value ("%zu", finite);
  info (" finite), ");
  value ("%zu", moved);
  info (" moved");
  if (cloud.height > 1)
  {
    info (", organised ");
    value ("%u x %u", cloud.width, cloud.height);
    info (" kept");
  }
  info ("\n  used: sigma ");
  value ("%g", filter.getUsedSigma ());
  info (", gamma ");
  value ("%g", filter.getUsedGamma ());
  if (filter.getAutomaticGamma ())
  {
    info (filter.getGammaSelection () == pcl_graph_denoise::GammaSelection::RISK_ESTIMATE
              ? " (lowest estimated risk, estimated noise "
              : " (derived, estimated noise ");
    value ("%g", filter.getEstimatedNoise ());
    info ("%s)", filter.getGraphIterations () > 1 ? " in the first pass" : "");
  }
  const auto &parts = filter.getGraphComponents ();
  if (parts.count > 1)
  {
    info ("\n  graph: ");
    value ("%zu", parts.count);
    info (" connected components (largest ");
    value ("%zu", parts.largest);
    info (" points), each smoothed on its own; ");
    value ("%zu", parts.isolated);
    info (" isolated points not moved");
  }
  info ("\n  solver%s: ", filter.getGraphIterations () > 1 ? " (last pass)" : "");
  value ("%d", report.iterations);
  info (" iterations, residual ");
  value ("%.3g", report.residual);
  info (", %s\n", report.converged ? "converged" : "NOT converged (tolerance not reached)");
}

/** Smooths x, y, z of every frame with a GraphSequenceSmoothing, streaming the frames
 *  through it (the batch result, frame by frame, with progress). */
void
smoothSequence (const Options &options, std::size_t s, const std::vector<XyzFields> &xyz,
                std::vector<CloudFile> &files)
{
  const Step &step = options.steps[s];
  const auto tikhonov = std::make_shared<pcl_graph_denoise::GraphTikhonovSmoothing<pcl::PointXYZ>> ();
  const auto tv = std::make_shared<pcl_graph_denoise::GraphTVSmoothing<pcl::PointXYZ>> ();
  const bool use_tv = step.has ("smoother") && step.parameters.at ("smoother").text == "tv";
  pcl_graph_denoise::GraphSmoothing<pcl::PointXYZ>::Ptr smoother;
  if (use_tv)
    smoother = tv;
  else
    smoother = tikhonov;
  configure (*smoother, step);
  configureSolvers (step, *tikhonov, *tv);
  pcl_graph_denoise::GraphSequenceSmoothing<pcl::PointXYZ> sequence;
  sequence.setSmoother (smoother);
  if (step.has ("k2"))
    sequence.setKTemporal (static_cast<int> (step.parameters.at ("k2").number));
  if (step.has ("window"))
    sequence.setTemporalWindow (static_cast<int> (step.parameters.at ("window").number));
  if (step.has ("motion_compensation"))
    sequence.setMotionCompensation (step.parameters.at ("motion_compensation").number != 0.0);
  info ("  %s smoother, k2 ", use_tv ? "TV" : "Tikhonov");
  value ("%d", sequence.getKTemporal ());
  info (", window ");
  value ("%d", sequence.getTemporalWindow ());
  info (", motion compensation ");
  value ("%s", sequence.getMotionCompensation () ? "on" : "off");
  info (", %zu frames\n", files.size ());

  std::vector<Cloud::Ptr> frames;
  for (std::size_t f = 0; f < files.size (); ++f)
    frames.push_back (xyz[f].extract (files[f].cloud));
  std::size_t done = 0;
  const auto store = [&] (const Cloud::Ptr &result) {
    const std::size_t f = done++;
    const std::size_t moved = xyz[f].writeBack (files[f].cloud, *frames[f], *result);
    info ("  frame ");
    value ("%zu/%zu", f + 1, files.size ());
    info (" (%s): ", options.inputs[f].c_str ());
    value ("%zu", frames[f]->size ());
    info (" points, ");
    value ("%zu", moved);
    info (" moved; gamma ");
    value ("%g", smoother->getUsedGamma ());
    const auto &report = smoother->getSolverReport ();
    info (", solver ");
    value ("%d", report.iterations);
    info (" iterations, %s\n", report.converged ? "converged" : "NOT converged");
  };
  const auto failed = [&] (const std::string &captured) {
    const std::string why = mainMessage (captured);
    return Error (stepName (options, s) + " failed on " + options.inputs[done] +
                  (why.empty () ? "" : ": " + why));
  };
  for (std::size_t f = 0; f < files.size (); ++f)
  {
    Cloud::Ptr ready;
    bool ok = false;
    const std::string captured = runReporting (*smoother, [&] { ok = sequence.push (frames[f], ready); });
    if (!ok)
      throw failed (captured);
    forward (captured);
    if (ready)
      store (ready);
  }
  std::vector<Cloud::Ptr> rest;
  bool ok = false;
  const std::string captured = runReporting (*smoother, [&] { ok = sequence.flush (rest); });
  for (const auto &result : rest)
    store (result);
  if (!ok)
    throw failed (captured);
  forward (captured);
}

/** Recomputes is_dense: true when every point has a finite x, y, z. */
void
updateDensity (const XyzFields &xyz, pcl::PCLPointCloud2 &cloud)
{
  cloud.is_dense = cloud.width * cloud.height == 0 || xyz.extract (cloud)->is_dense;
}

int
fail (const std::string &message, int code)
{
  pcl::console::print_error (stderr, "%s: error: %s\n", program, printable (message, 400).c_str ());
  return code;
}

int
run (const Options &options)
{
  pcl::console::TicToc total;
  total.tic ();
  for (const auto &output : options.outputs)
    PendingFiles::checkWritable (output);
  if (!options.removed.empty ())
    PendingFiles::checkWritable (options.removed);

  pcl::console::TicToc timer;
  std::vector<CloudFile> files;
  std::vector<XyzFields> xyz;
  for (const auto &input : options.inputs)
  {
    timer.tic ();
    files.push_back (loadCloud (input));
    const pcl::PCLPointCloud2 &cloud = files.back ().cloud;
    xyz.emplace_back (cloud, input);
    const std::size_t size = std::size_t (cloud.width) * cloud.height;
    const std::size_t finite = countFinite (*xyz.back ().extract (cloud));
    if (finite == 0)
      throw Error (input + ": no point has a finite x, y, z");
    highlight ("Loading ");
    value ("%s ", input.c_str ());
    info ("[done, ");
    value ("%g", timer.toc ());
    info (" ms : ");
    value ("%zu", size);
    info (" points, ");
    if (cloud.height > 1)
    {
      info ("organised ");
      value ("%u x %u", cloud.width, cloud.height);
      info (", ");
    }
    value ("%zu", finite);
    info (" with a finite x, y, z]\n  Available dimensions: ");
    value ("%s\n", pcl::getFieldsList (cloud).c_str ());
  }

  // Double coordinates about an origin (geo-referenced clouds): one for all the frames
  // of a sequence, one per file otherwise.
  const bool temporal = std::any_of (options.steps.begin (), options.steps.end (),
                                     [] (const Step &step) { return step.kind == StepKind::TEMPORAL; });
  if (temporal)
  {
    std::vector<const pcl::PCLPointCloud2 *> clouds;
    for (const auto &file : files)
      clouds.push_back (&file.cloud);
    setCommonOrigin (xyz, clouds);
  }
  else
    for (std::size_t f = 0; f < files.size (); ++f)
      xyz[f].centreOn (files[f].cloud);

  pcl::PCLPointCloud2 removed;
  for (std::size_t s = 0; s < options.steps.size (); ++s)
  {
    const Step &step = options.steps[s];
    highlight ("Step %zu/%zu: ", s + 1, options.steps.size ());
    value ("%s", stepOption (step.kind));
    info (" (%s)%s, parameters set: %s\n", stepClass (step.kind),
          options.default_chain ? ", default chain" : "", describeParameters (step).c_str ());
    timer.tic ();
    if (step.kind == StepKind::TEMPORAL)
      smoothSequence (options, s, xyz, files);
    else
      for (std::size_t f = 0; f < files.size (); ++f)
      {
        if (files.size () > 1)
        {
          info ("  frame ");
          value ("%zu/%zu", f + 1, files.size ());
          info (" (%s)\n", options.inputs[f].c_str ());
        }
        if (step.kind == StepKind::OUTLIERS)
          removeOutliers (options, s, xyz[f], files[f].cloud, removed);
        else
          smooth (options, s, xyz[f], files[f].cloud);
      }
    info ("  [done, ");
    value ("%g", timer.toc ());
    info (" ms]\n");
  }
  for (std::size_t f = 0; f < files.size (); ++f)
    if (files[f].cloud.width * files[f].cloud.height == 0)
      throw Error ((files.size () > 1 ? options.inputs[f] + ": " : std::string ()) +
                   "no point is left after the steps: nothing to write");

  PendingFiles outputs;
  const auto save = [&] (const std::string &path, const CloudFile &cloud) {
    timer.tic ();
    outputs.write (path, cloud, options.binary);
    highlight ("Saving ");
    value ("%s ", path.c_str ());
    info ("(%s) [done, ", options.binary ? "binary" : "ASCII");
    value ("%g", timer.toc ());
    info (" ms : ");
    value ("%u", cloud.cloud.width * cloud.cloud.height);
    info (" points]\n");
  };
  for (std::size_t f = 0; f < files.size (); ++f)
  {
    updateDensity (xyz[f], files[f].cloud);
    save (options.outputs[f], files[f]);
  }
  if (!options.removed.empty ())
  {
    CloudFile gone;
    gone.cloud = removed.fields.empty () ? selectPoints (files[0].cloud, {}) : removed;
    gone.origin = files[0].origin;
    gone.orientation = files[0].orientation;
    updateDensity (xyz[0], gone.cloud);
    save (options.removed, gone);
  }
  outputs.commit ();
  highlight ("Done in ");
  value ("%g", total.toc ());
  info (" ms\n");
  return 0;
}

}  // namespace

int
main (int argc, char **argv)
{
  Options options;
  try
  {
    options = parseCommandLine (argc, argv);
  }
  catch (const UsageError &e)
  {
    return fail (e.what (), 2);
  }
  if (options.help)
  {
    std::fputs (usage (program).c_str (), stdout);
    return 0;
  }
  quiet = options.quiet;
  pcl::console::setVerbosityLevel (quiet ? pcl::console::L_WARN : pcl::console::L_INFO);
  try
  {
    return run (options);
  }
  catch (const Error &e)
  {
    return fail (e.what (), 1);
  }
  catch (const std::bad_alloc &)
  {
    return fail ("out of memory", 1);
  }
  catch (const std::exception &e)
  {
    return fail (e.what (), 1);
  }
}

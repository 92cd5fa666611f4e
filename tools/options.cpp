/*
 * pcl_graph_denoise: graph-signal-processing point cloud denoising for PCL.
 * SPDX-License-Identifier: BSD-3-Clause
 */
#include "options.h"

#include "cloud_io.h"
#include "stderr_capture.h"

#include <pcl_graph_denoise/graph_degree_outlier_removal.h>
#include <pcl_graph_denoise/graph_sequence_smoothing.h>
#include <pcl_graph_denoise/graph_tikhonov_smoothing.h>
#include <pcl_graph_denoise/graph_tv_smoothing.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <limits>
#include <sstream>
#include <system_error>

namespace pcl_graph_denoise {
namespace tools {

namespace {

/** Which steps have a parameter. */
enum StepMask : unsigned
{
  OUTLIERS_STEP = 1,
  TIKHONOV_STEP = 2,
  TV_STEP = 4,
  TEMPORAL_STEP = 8,
  SMOOTHING_STEPS = TIKHONOV_STEP | TV_STEP | TEMPORAL_STEP,
  ALL_STEPS = OUTLIERS_STEP | SMOOTHING_STEPS
};

enum class ValueType
{
  NON_NEGATIVE,  ///< finite real >= 0
  POSITIVE,      ///< finite real > 0
  FRACTION,      ///< real in [0, 1]
  AT_LEAST_ONE,  ///< integer >= 1
  PASSES,        ///< integer in [1, kMaxGraphIterations]
  THREADS,       ///< integer in [0, max_threads]
  COUNT,         ///< integer >= 0
  SWITCH,        ///< 0 or 1 (also true/false, on/off, yes/no)
  GAMMA,         ///< "auto", "risk" or a finite real >= 0
  SURFACE,       ///< plane, quadric or blended
  SOLVER,        ///< cg or cholmod
  SMOOTHER,      ///< tikhonov or tv
  NORM           ///< isotropic or anisotropic
};

struct ParameterSpec
{
  const char *name;
  unsigned steps;
  ValueType type;
};

constexpr int max_threads = 1024;

const ParameterSpec parameter_specs[] = {
    {"radius", OUTLIERS_STEP, ValueType::NON_NEGATIVE},
    {"threshold_ratio", OUTLIERS_STEP, ValueType::NON_NEGATIVE},
    {"degree_threshold", OUTLIERS_STEP, ValueType::NON_NEGATIVE},
    {"outlier_fraction", OUTLIERS_STEP, ValueType::FRACTION},
    {"residual_threshold", OUTLIERS_STEP, ValueType::NON_NEGATIVE},
    {"keep_sparse_surfaces", OUTLIERS_STEP, ValueType::SWITCH},
    {"keep_organized", OUTLIERS_STEP, ValueType::SWITCH},
    {"sigma", ALL_STEPS, ValueType::NON_NEGATIVE},
    {"k", SMOOTHING_STEPS, ValueType::AT_LEAST_ONE},
    {"gamma", SMOOTHING_STEPS, ValueType::GAMMA},
    {"graph_iterations", SMOOTHING_STEPS, ValueType::PASSES},
    {"normal_displacement", SMOOTHING_STEPS, ValueType::SWITCH},
    {"local_surface", SMOOTHING_STEPS, ValueType::SURFACE},
    {"adaptive_support", SMOOTHING_STEPS, ValueType::SWITCH},
    {"patch_cover", SMOOTHING_STEPS, ValueType::COUNT},
    {"shrinkage_correction", SMOOTHING_STEPS, ValueType::SWITCH},
    {"density_normalization", SMOOTHING_STEPS, ValueType::SWITCH},
    {"tolerance", SMOOTHING_STEPS, ValueType::POSITIVE},
    {"max_iterations", SMOOTHING_STEPS, ValueType::AT_LEAST_ONE},
    {"solver", TIKHONOV_STEP | TEMPORAL_STEP, ValueType::SOLVER},
    {"norm", TV_STEP | TEMPORAL_STEP, ValueType::NORM},
    {"smoother", TEMPORAL_STEP, ValueType::SMOOTHER},
    {"k2", TEMPORAL_STEP, ValueType::COUNT},
    {"window", TEMPORAL_STEP, ValueType::COUNT},
    {"motion_compensation", TEMPORAL_STEP, ValueType::SWITCH},
    {"threads", ALL_STEPS, ValueType::THREADS},
    {"memory_limit", ALL_STEPS, ValueType::NON_NEGATIVE},
};

/** The three ways of choosing the outliers' threshold: one per step at most. */
const char *const threshold_rules[] = {"threshold_ratio", "degree_threshold", "outlier_fraction"};

const StepKind kAllSteps[] = {StepKind::OUTLIERS, StepKind::TIKHONOV, StepKind::TV,
                              StepKind::TEMPORAL};

unsigned
maskOf (StepKind kind)
{
  switch (kind)
  {
  case StepKind::OUTLIERS:
    return OUTLIERS_STEP;
  case StepKind::TIKHONOV:
    return TIKHONOV_STEP;
  case StepKind::TEMPORAL:
    return TEMPORAL_STEP;
  case StepKind::TV:
    break;
  }
  return TV_STEP;
}

const ParameterSpec *
findParameter (const std::string &name)
{
  for (const auto &spec : parameter_specs)
    if (name == spec.name)
      return &spec;
  return nullptr;
}

bool
findStep (const std::string &name, StepKind &kind)
{
  for (const StepKind k : kAllSteps)
    if (name == stepOption (k))
    {
      kind = k;
      return true;
    }
  return false;
}

std::string
stepsHaving (unsigned mask)
{
  std::string names;
  for (const StepKind k : kAllSteps)
    if (mask & maskOf (k))
      names += std::string (names.empty () ? "" : ", ") + stepOption (k);
  return names;
}

/** A whole argument as a finite real number in decimal notation (strtod alone would
 *  also read hexadecimal: "0x10" as 16). */
bool
parseReal (const std::string &text, double &value)
{
  if (text.empty () || text.find_first_not_of ("0123456789+-.eE") != std::string::npos)
    return false;
  char *end = nullptr;
  errno = 0;
  value = std::strtod (text.c_str (), &end);
  return end == text.c_str () + text.size () && errno != ERANGE && std::isfinite (value);
}

/** Checks a value against its parameter's type. */
ParameterValue
parseValue (const ParameterSpec &spec, const std::string &text)
{
  const std::string option = std::string ("-") + spec.name;
  const auto invalid = [&] (const std::string &why) {
    return UsageError ("invalid value '" + printable (text, 40) + "' for " + option + ": " + why);
  };
  ParameterValue value;
  value.text = text;
  switch (spec.type)
  {
  case ValueType::SWITCH:
    if (text == "1" || text == "true" || text == "on" || text == "yes")
      value.number = 1.0;
    else if (text == "0" || text == "false" || text == "off" || text == "no")
      value.number = 0.0;
    else
      throw invalid ("expected 0 or 1");
    return value;
  case ValueType::SURFACE:
  {
    LocalSurface surface;
    if (!localSurfaceFromName (text, surface))
      throw invalid ("expected plane, quadric or blended");
  }
    return value;
  case ValueType::SOLVER:
    if (text != "cg" && text != "cholmod")
      throw invalid ("expected cg or cholmod");
    return value;
  case ValueType::NORM:
    if (text != "isotropic" && text != "anisotropic")
      throw invalid ("expected isotropic or anisotropic");
    return value;
  case ValueType::SMOOTHER:
    if (text != "tikhonov" && text != "tv")
      throw invalid ("expected tikhonov or tv");
    return value;
  case ValueType::AT_LEAST_ONE:
  case ValueType::PASSES:
  case ValueType::THREADS:
  case ValueType::COUNT:
  {
    const std::string digits = !text.empty () && text[0] == '+' ? text.substr (1) : text;
    if (digits.empty () || !std::all_of (digits.begin (), digits.end (),
                                         [] (unsigned char c) { return std::isdigit (c); }))
    {
      double real;
      if (!parseReal (text, real))
        throw invalid ("not a number");
      if (real < 0.0)
        throw invalid (spec.type == ValueType::THREADS || spec.type == ValueType::COUNT
                           ? "must be >= 0"
                           : "must be >= 1");
      throw invalid ("not an integer");
    }
    const int limit = spec.type == ValueType::THREADS  ? max_threads
                      : spec.type == ValueType::PASSES ? pcl_graph_denoise::kMaxGraphIterations
                                                       : std::numeric_limits<int>::max ();
    if (digits.size () > 10 || std::stoll (digits) > limit)
      throw invalid ("must be at most " + std::to_string (limit));
    value.number = static_cast<double> (std::stoll (digits));
    if (spec.type != ValueType::THREADS && spec.type != ValueType::COUNT && value.number < 1.0)
      throw invalid ("must be >= 1");
    return value;
  }
  case ValueType::GAMMA:
    if (text == "auto" || text == "risk")
      return value;
    [[fallthrough]];
  case ValueType::NON_NEGATIVE:
  case ValueType::POSITIVE:
  case ValueType::FRACTION:
    if (!parseReal (text, value.number))
      throw invalid (std::isnan (std::strtod (text.c_str (), nullptr)) ||
                             std::isinf (std::strtod (text.c_str (), nullptr))
                         ? "must be a finite number"
                         : "not a number");
    if (value.number < 0.0)
      throw invalid ("must be >= 0");
    if (spec.type == ValueType::POSITIVE && value.number == 0.0)
      throw invalid ("must be > 0");
    if (spec.type == ValueType::FRACTION && value.number > 1.0)
      throw invalid ("must be in [0, 1]");
    value.text.clear ();
    return value;
  }
  return value;
}

/** Sets a parameter once in a set of parameters. */
void
setParameter (std::map<std::string, ParameterValue> &parameters, const ParameterSpec &spec,
              const std::string &text, const std::string &where)
{
  if (parameters.count (spec.name))
    throw UsageError (std::string ("-") + spec.name + " given twice " + where);
  parameters[spec.name] = parseValue (spec, text);
}

bool
hasExtension (const std::string &arg)
{
  std::string lower = arg;
  std::transform (lower.begin (), lower.end (), lower.begin (),
                  [] (unsigned char c) { return static_cast<char> (std::tolower (c)); });
  const auto ends = [&] (const char *ext) {
    return lower.size () >= 4 && lower.compare (lower.size () - 4, 4, ext) == 0;
  };
  return ends (".pcd") || ends (".ply");
}

/** A file name argument: .pcd or .ply (a usage error otherwise). */
std::string
fileArgument (const std::string &arg)
{
  try
  {
    formatOf (arg);
  }
  catch (const Error &e)
  {
    throw UsageError (e.what ());
  }
  return arg;
}

}  // namespace

Options
parseCommandLine (int argc, const char *const *argv)
{
  Options options;
  for (int i = 1; i < argc; ++i)
    if (std::string (argv[i]) == "-h" || std::string (argv[i]) == "--help")
    {
      options.help = true;
      return options;
    }

  std::vector<std::string> files;
  std::map<std::string, ParameterValue> chain_wide;  // step parameters before any step
  const auto where = [&] () {
    return options.steps.empty ()
               ? std::string ("before the first step")
               : std::string ("for step ") + std::to_string (options.steps.size ()) + " (" +
                     stepOption (options.steps.back ().kind) + ")";
  };
  const auto setStepParameter = [&] (const std::string &name, const std::string &text) {
    const ParameterSpec *spec = findParameter (name);
    if (!spec)
      throw UsageError ("unknown option '-" + printable (name, 40) + "' (see -h)");
    if (options.steps.empty ())
      setParameter (chain_wide, *spec, text, where ());
    else
    {
      Step &step = options.steps.back ();
      if (!(spec->steps & maskOf (step.kind)))
        throw UsageError (std::string ("-") + spec->name + " does not apply to " +
                          stepOption (step.kind) + " (only to " + stepsHaving (spec->steps) + ")");
      setParameter (step.parameters, *spec, text, where ());
    }
  };

  for (int i = 1; i < argc; ++i)
  {
    const std::string arg = argv[i];
    if (arg.size () < 2 || arg[0] != '-' || std::isdigit (static_cast<unsigned char> (arg[1])) ||
        arg[1] == '.')
    {
      // The compact form of step parameters, "-tv gamma=0.5,k=12": a word with '=' that
      // does not name a cloud file.
      if (arg.find ('=') == std::string::npos || hasExtension (arg))
      {
        files.push_back (arg);
        continue;
      }
      std::istringstream list (arg);
      std::string item;
      while (std::getline (list, item, ','))
      {
        const auto equal = item.find ('=');
        if (equal == std::string::npos || equal == 0)
          throw UsageError ("invalid parameter '" + printable (item, 40) + "' in '" +
                            printable (arg, 80) + "': expected name=value");
        setStepParameter (item.substr (0, equal), item.substr (equal + 1));
      }
      continue;
    }
    StepKind kind;
    if (findStep (arg, kind))
    {
      options.steps.push_back (Step{kind, {}});
      continue;
    }
    const std::string name = arg.substr (1);
    if (name == "q")
      options.quiet = true;
    else if (name == "ascii")
    {
      options.binary = false;
      if (i + 1 < argc && (std::string (argv[i + 1]) == "0" || std::string (argv[i + 1]) == "1"))
        options.binary = std::string (argv[++i]) == "0";
    }
    else if (name == "removed")
    {
      if (i + 1 >= argc)
        throw UsageError ("-removed needs a file name");
      if (!options.removed.empty ())
        throw UsageError ("-removed given twice");
      options.removed = fileArgument (argv[++i]);
    }
    else
    {
      if (!findParameter (name))
        throw UsageError ("unknown option '" + printable (arg, 40) + "' (see -h)");
      if (i + 1 >= argc)
        throw UsageError (arg + " needs a value");
      setStepParameter (name, argv[++i]);
    }
  }

  const bool temporal = std::any_of (options.steps.begin (), options.steps.end (),
                                     [] (const Step &s) { return s.kind == StepKind::TEMPORAL; });
  if (files.empty ())
    throw UsageError (temporal ? "missing the input files and the output folder (see -h)"
                               : "missing the input and output files (see -h)");
  if (files.size () == 1)
    throw UsageError (temporal ? "missing the output folder (the last argument, see -h)"
                               : "missing the output file (see -h)");
  if (temporal)
  {
    // A sequence: the inputs in time order, then the folder of the results, each under
    // its input's file name.
    namespace fs = std::filesystem;
    std::error_code ec;
    const fs::path folder = files.back ();
    if (hasExtension (files.back ()))
      throw UsageError ("with -temporal the last argument is the output folder, not a file ('" +
                        printable (files.back (), 80) + "')");
    if (!fs::is_directory (folder, ec))
      throw UsageError ("output folder '" + printable (files.back (), 80) + "' does not exist");
    std::vector<std::string> names;
    for (std::size_t f = 0; f + 1 < files.size (); ++f)
    {
      const std::string input = fileArgument (files[f]);
      const std::string name = fs::path (input).filename ().string ();
      if (std::find (names.begin (), names.end (), name) != names.end ())
        throw UsageError ("two inputs are named '" + printable (name, 80) +
                          "': their results would overwrite each other in the output folder");
      names.push_back (name);
      const std::string output = (folder / name).string ();
      if (fs::weakly_canonical (fs::absolute (output, ec), ec) ==
          fs::weakly_canonical (fs::absolute (input, ec), ec))
        throw UsageError ("the output folder holds the input '" + printable (input, 80) +
                          "': its result would overwrite it");
      options.inputs.push_back (input);
      options.outputs.push_back (output);
    }
    options.input = options.inputs.front ();
    options.output = options.outputs.front ();
  }
  else
  {
    if (files.size () > 2)
      throw UsageError ("unexpected argument '" + printable (files[2], 80) +
                        "': one input and one output file (several inputs need a -temporal step)");
    options.input = fileArgument (files[0]);
    options.output = fileArgument (files[1]);
    options.inputs = {options.input};
    options.outputs = {options.output};
  }

  if (options.steps.empty ())
  {
    options.default_chain = true;
    options.steps.push_back (Step{StepKind::OUTLIERS, {}});
    options.steps.push_back (Step{StepKind::TV, {}});
  }
  // -solver belongs to the Tikhonov smoother, -norm to TV: a -temporal step takes the one
  // of its -smoother (given for the step itself: an error otherwise; given before the
  // steps: not passed on).
  const auto smootherOf = [] (const Step &step) {
    return step.has ("smoother") ? step.parameters.at ("smoother").text : std::string ("tikhonov");
  };
  const auto appliesTo = [&] (const std::string &name, const Step &step) {
    return step.kind != StepKind::TEMPORAL ||
           !((name == "solver" && smootherOf (step) != "tikhonov") ||
             (name == "norm" && smootherOf (step) != "tv"));
  };
  for (std::size_t s = 0; s < options.steps.size (); ++s)
    for (const char *name : {"solver", "norm"})
      if (options.steps[s].has (name) && !appliesTo (name, options.steps[s]))
        throw UsageError ("step " + std::to_string (s + 1) + " (-temporal): -" + name +
                          " does not apply to -smoother " + smootherOf (options.steps[s]));
  // Parameters given before the first step go to every step that has them, unless the
  // step sets them itself (for the outliers' threshold: any of the three rules).
  if (std::count_if (std::begin (threshold_rules), std::end (threshold_rules),
                     [&] (const char *r) { return chain_wide.count (r) > 0; }) > 1)
    throw UsageError ("before the steps: give only one of -threshold_ratio, -degree_threshold "
                      "and -outlier_fraction");
  for (const auto &[name, value] : chain_wide)
  {
    const ParameterSpec &spec = *findParameter (name);
    const bool rule = std::find (std::begin (threshold_rules), std::end (threshold_rules), name) !=
                      std::end (threshold_rules);
    bool used = false;
    for (Step &step : options.steps)
    {
      if (!(spec.steps & maskOf (step.kind)))
        continue;
      used = true;
      if (!appliesTo (name, step))
        continue;
      bool own = step.has (name);
      if (rule)
        for (const char *r : threshold_rules)
          own = own || step.has (r);
      if (!own)
        step.parameters[name] = value;
    }
    if (!used)
      throw UsageError ("-" + name + " (given before the steps) applies to none of them (only to " +
                        stepsHaving (spec.steps) + ")");
  }
  for (std::size_t s = 0; s < options.steps.size (); ++s)
  {
    const Step &step = options.steps[s];
    if (std::count_if (std::begin (threshold_rules), std::end (threshold_rules),
                       [&] (const char *r) { return step.has (r); }) > 1)
      throw UsageError ("step " + std::to_string (s + 1) + " (" + stepOption (step.kind) +
                        "): give only one of -threshold_ratio, -degree_threshold and "
                        "-outlier_fraction");
  }
  if (!options.removed.empty () && temporal)
    throw UsageError ("-removed is not available with -temporal (several inputs)");
  if (!options.removed.empty ())
  {
    if (std::none_of (options.steps.begin (), options.steps.end (),
                      [] (const Step &s) { return s.kind == StepKind::OUTLIERS; }))
      throw UsageError ("-removed needs an -outliers step in the chain");
    namespace fs = std::filesystem;
    std::error_code ec;
    const auto resolved = [&] (const std::string &path) {
      return fs::weakly_canonical (fs::absolute (path, ec), ec);
    };
    if (options.removed == options.output ||
        resolved (options.removed) == resolved (options.output))
      throw UsageError ("-removed names the output file");
    // The input would be replaced by its outliers alone.
    if (options.removed == options.input || resolved (options.removed) == resolved (options.input))
      throw UsageError ("-removed names the input file: it would be replaced by the removed points");
  }
  return options;
}

std::string
usage (const std::string &program)
{
  // The defaults are the filters' own.
  const GraphDegreeOutlierRemoval<pcl::PointXYZ> outliers;
  const GraphTikhonovSmoothing<pcl::PointXYZ> tikhonov;
  const GraphTVSmoothing<pcl::PointXYZ> tv;
  const GraphSequenceSmoothing<pcl::PointXYZ> sequence;
  const bool temporal_tv =
      dynamic_cast<const GraphTVSmoothing<pcl::PointXYZ> *> (sequence.getSmoother ().get ()) != nullptr;
  const auto text = [] (double v) {
    std::ostringstream s;
    s << v;
    return s.str ();
  };
  const auto derived = [&] (double v, const char *rule) {
    return v == 0.0 ? std::string ("0 = ") + rule : text (v);
  };
  const auto both = [&] (double t, double v) {
    return t == v ? text (t) : text (t) + " -tikhonov, " + text (v) + " -tv";
  };
  const auto threads = [&] (int n) {
    return n == 0 ? std::string ("0 = all cores") : std::to_string (n);
  };
  const std::string radius = derived (outliers.getRadiusSearch (), "3 x spacing, derived");
  const std::string outlier_sigma = derived (outliers.getSigma (), "the spacing, derived");
  const std::string ratio = text (outliers.getAutomaticThresholdRatio ());
  const std::string residual = text (outliers.getResidualThreshold ());
  const std::string outlier_threads = threads (outliers.getNumberOfThreads ());
  const std::string k = both (tikhonov.getKSearch (), tv.getKSearch ());
  const std::string sigma = derived (tv.getSigma (), "mean k-NN distance / sqrt 2");
  const std::string gamma = tv.getAutomaticGamma () && tikhonov.getAutomaticGamma ()
                                ? "auto, derived from the estimated noise"
                                : both (tikhonov.getGamma (), tv.getGamma ());
  const std::string passes = both (tikhonov.getGraphIterations (), tv.getGraphIterations ());
  const std::string normal = both (tikhonov.getNormalDisplacement (), tv.getNormalDisplacement ());
  const char *surface = localSurfaceName (tv.getLocalSurface ());
  const std::string twicing =
      both (tikhonov.getShrinkageCorrection (), tv.getShrinkageCorrection ());
  const std::string adaptive = both (tikhonov.getAdaptiveSupport (), tv.getAdaptiveSupport ());
  const std::string density =
      both (tikhonov.getDensityNormalization (), tv.getDensityNormalization ());
  const std::string cover = both (tikhonov.getPatchCover (), tv.getPatchCover ());
  const std::string tolerance = both (tikhonov.getTolerance (), tv.getTolerance ());
  GraphTikhonovSmoothing<pcl::PointXYZ> plain_tikhonov;  // the paper's: no quadrics
  GraphTVSmoothing<pcl::PointXYZ> plain_tv;
  plain_tikhonov.setNormalDisplacement (false);
  plain_tv.setNormalDisplacement (false);
  const std::string plain_tolerance = both (plain_tikhonov.getTolerance (), plain_tv.getTolerance ());
  const std::string iterations =
      both (tikhonov.getMaximumIterations (), tv.getMaximumIterations ());
  const char *solver = tikhonov.getSolver () == core::TikhonovSolver::CHOLMOD ? "cholmod" : "cg";
  const char *norm =
      tv.getNorm () == core::TotalVariationNorm::ANISOTROPIC ? "anisotropic" : "isotropic";
  const std::string smoothing_threads = threads (tv.getNumberOfThreads ());
  const std::string p = "  " + program;

  std::ostringstream u;
  u << "Usage: " << program << " input.{pcd,ply} output.{pcd,ply} [options]\n"
    << "         [step [step options]]...\n"
    << "       " << program << " frame.{pcd,ply}... output_folder [options]\n"
    << "         [step [step options]]...   (with a -temporal step: a sequence)\n"
    << "\n"
    << "Graph-based point cloud denoising (Schoenenberger, Paratte, Vandergheynst 2015): the\n"
    << "steps run in the order given, each on the previous one's result. Every field of the\n"
    << "input (colour, normals, intensity, custom fields) is kept: smoothing moves only x, y, z\n"
    << "and keeps the size, order and organisation (width x height) of the cloud; outlier\n"
    << "removal drops whole points. Files are .pcd or .ply, by extension; x, y, z must be\n"
    << "float or double. Between .pcd and .ply, fields follow PCL's PLY conventions (rgb\n"
    << "as red, green, blue: the alpha byte of a PCD rgb is not kept).\n"
    << "\n"
    << "Steps (each may repeat; with none: -outliers -tv, as in the demo):\n"
    << "  -outliers    GraphDegreeOutlierRemoval: removes the points of low weighted degree\n"
    << "               in an epsilon-radius graph; points with a non-finite x, y, z go too\n"
    << "  -tikhonov    GraphTikhonovSmoothing: (I + 2 gamma L) x = f on the k-NN graph\n"
    << "  -tv          GraphTVSmoothing: graph total variation, keeps edges sharper\n"
    << "  -temporal    GraphSequenceSmoothing: the inputs are the frames of a sequence (in\n"
    << "               time order, one coordinate system); each frame is smoothed on the\n"
    << "               spatio-temporal graph of its neighbouring frames. The other steps run\n"
    << "               on each frame alone. The last argument is then an existing folder,\n"
    << "               where each result is written under its input's file name\n"
    << "Smoothing steps leave points with a non-finite x, y, z where they are.\n"
    << "\n"
    << "Step options follow their step and set it alone, as \"-name value\" or as\n"
    << "\"name=value,name=value\" words (both forms mix). Given before the first step, a\n"
    << "step option sets every step that has it and does not set it itself. A parameter not\n"
    << "given keeps the filter's default, most of them derived from the data.\n"
    << p << " in.pcd out.pcd -outliers -outlier_fraction 0.02 -tv -gamma 0.004 -k 12\n"
    << p << " in.pcd out.pcd -outliers outlier_fraction=0.02 -tv gamma=0.004,k=12\n"
    << p << " in.ply out.ply -threads 4 -tikhonov -tv -removed gone.ply\n"
    << "\n"
    << "-outliers options (default rule: -threshold_ratio):\n"
    << "  -radius X               epsilon, points closer than X are linked; cloud units, >= 0\n"
    << "                          (default: " << radius << ")\n"
    << "  -sigma X                theta of the weights exp(-d^2 / (2 theta^2)); >= 0\n"
    << "                          (default: " << outlier_sigma << ")\n"
    << "  -threshold_ratio X      remove degree < X x first quartile of the degrees; >= 0\n"
    << "                          (default: " << ratio << ")\n"
    << "  -degree_threshold X     remove degree < X (a sum of weights); >= 0 (default: unused)\n"
    << "  -outlier_fraction X     remove the fraction X of lowest-degree points; in [0, 1]\n"
    << "                          (default: unused)\n"
    << "                          (one of these three rules per step)\n"
    << "  -residual_threshold X   also remove points off their neighbours' plane by more than\n"
    << "                          X x the noise; 0 = off (the paper's filter); >= 0; not with\n"
    << "                          -outlier_fraction (default: " << residual << ")\n"
    << "  -keep_sparse_surfaces 0|1  with -threshold_ratio, 1 keeps the low-degree points on a\n"
    << "                          surface sampled more sparsely than the rest (a far wall);\n"
    << "                          isolated and off-surface points still go (default: "
    << (outliers.getKeepSparseSurfaces () ? 1 : 0) << ")\n"
    << "  -keep_organized 0|1     1: removed points stay, with x, y, z set to NaN, so that\n"
    << "                          width x height survive (default: 0, they are dropped)\n"
    << "  -threads N              worker threads (default: " << outlier_threads << ")\n"
    << "  -memory_limit MB        refuse up front a cloud whose estimated peak memory is\n"
    << "                          above MB megabytes; 0 = this machine's memory (default: 0)\n"
    << "\n"
    << "-tikhonov, -tv and -temporal options:\n"
    << "  -k N                    neighbours per point in the graph; >= 1 (default: " << k << ")\n"
    << "  -sigma X                theta of the weights; >= 0\n"
    << "                          (default: " << sigma << ")\n"
    << "  -gamma X|auto|risk      strength, >= 0, 0 = identity; -tikhonov: unitless, -tv: a\n"
    << "                          length in cloud units; auto = the rule, risk = the rule's\n"
    << "                          gamma x 1/4 .. 16 with the lowest estimated error (slower)\n"
    << "                          (default: " << gamma << ")\n"
    << "  -graph_iterations N     passes, each on a graph rebuilt from the previous one; 1 to "
       << pcl_graph_denoise::kMaxGraphIterations << "\n"
    << "                          (default: " << passes << ")\n"
    << "  -normal_displacement 0|1\n"
    << "                          move points only along the fitted normal (default: " << normal
    << ")\n"
    << "  -local_surface plane|quadric|blended\n"
    << "                          what a point moves onto along its normal: the fitted plane,\n"
    << "                          a robust quadric (over two or three graph rings), or the\n"
    << "                          mean of the quadrics around it (default: " << surface << ")\n"
    << "  -adaptive_support 0|1   fit each quadric over three graph rings where that agrees\n"
    << "                          with the two-ring fit (within 2 sqrt(6) noise levels), else\n"
    << "                          over two, and halve the derived gamma; 0: two rings, in\n"
    << "                          0.6-1.0x the time; quadric local surfaces only (default: "
    << adaptive << ")\n"
    << "  -patch_cover N          blended quadrics: a point gets a quadric of its own unless N\n"
    << "                          graph neighbours before it have one; 0: every point, about\n"
    << "                          0.7% less error for 1.4-1.7x the time; >= 0 (default: " << cover
    << ")\n"
    << "  -shrinkage_correction 0|1\n"
    << "                          twicing against the shrinkage of curved surfaces (default: "
    << twicing << ")\n"
    << "  -density_normalization 0|1\n"
    << "                          divide the sampling density out of the graph's weights, so\n"
    << "                          that dense and sparse parts are smoothed alike; with normal\n"
    << "                          displacement only (default: " << density << ")\n"
    << "  -tolerance X            solver stop: CG relative residual (-tikhonov), relative\n"
    << "                          primal-dual gap (-tv); > 0 (default: " << tolerance << ";\n"
    << "                          without quadrics, -normal_displacement 0 or -local_surface\n"
    << "                          plane: " << plain_tolerance << ")\n"
    << "  -max_iterations N       solver iterations per pass; >= 1\n"
    << "                          (default: " << iterations << ")\n"
    << "  -solver cg|cholmod      Tikhonov only (default: " << solver << ")\n"
    << "  -norm isotropic|anisotropic\n"
    << "                          TV only (default: " << norm << ")\n"
    << "  -threads N              worker threads (default: " << smoothing_threads << ")\n"
    << "  -memory_limit MB        refuse up front a cloud whose estimated peak memory is\n"
    << "                          above MB megabytes; 0 = this machine's memory (default: 0)\n"
    << "\n"
    << "-temporal options (and the smoothing options above, for its smoother):\n"
    << "  -smoother tikhonov|tv   the smoothing run on the spatio-temporal graph\n"
    << "                          (default: " << (temporal_tv ? "tv" : "tikhonov") << ")\n"
    << "  -k2 N                   neighbours of each point in each other frame of the\n"
    << "                          window (k is those in its own frame); 0 = frame by frame\n"
    << "                          (default: " << sequence.getKTemporal () << ")\n"
    << "  -window N               frames t - N ... t + N take part in frame t (default: "
    << sequence.getTemporalWindow () << ")\n"
    << "  -motion_compensation 0|1\n"
    << "                          move the other frames onto frame t's surface first (rigid\n"
    << "                          fit, then along the normals), for surfaces that move; 0 =\n"
    << "                          the paper's graph on the frames as they are (default: " << (sequence.getMotionCompensation () ? 1 : 0) << ")\n"
    << p << " f0.pcd f1.pcd f2.pcd out_folder -outliers -temporal k2=3\n"
    << "\n"
    << "Other options:\n"
    << "  -removed FILE           also write the points removed by the -outliers steps, with\n"
    << "                          all their fields, to FILE (.pcd or .ply) (default: none)\n"
    << "  -ascii [0|1]            write ASCII files instead of binary (default: 0, binary)\n"
    << "  -q                      quiet: only warnings and errors (default: report each step)\n"
    << "  -h, --help              this text\n"
    << "\n"
    << "The report (steps, times, points, what the solvers did) goes to stderr. Outputs are\n"
    << "written under a temporary name and renamed when complete: a failure leaves none.\n"
    << "Exit code: 0 done, 1 unreadable input or failed step or write, 2 invalid command line.\n";
  return u.str ();
}

}  // namespace tools
}  // namespace pcl_graph_denoise

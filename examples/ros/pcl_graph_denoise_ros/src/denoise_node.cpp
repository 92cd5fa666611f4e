/*
 * pcl_graph_denoise: graph-signal-processing point cloud denoising for PCL.
 * SPDX-License-Identifier: BSD-3-Clause
 *
 * denoise_node: a ROS 1 node that runs a chain of the library's filters on every
 * sensor_msgs/PointCloud2 it receives on `input` and publishes the result on `output`
 * with the same header (frame_id and stamp, to the nanosecond) and every field of the
 * input. Smoothing moves only x, y, z and keeps the size, order and organisation of
 * the cloud; outlier removal drops whole points. See docs/ros.md for the parameters.
 *
 * A cloud that cannot be filtered (empty, malformed, without float x/y/z, no finite
 * point, a filter error) is reported with ROS_ERROR and nothing is published for it.
 * Invalid parameters are reported at start-up and the node exits with status 1.
 */
#include "cloud_fields.h"
#include "steps.h"

#include <pcl_graph_denoise/graph_degree_outlier_removal.h>
#include <pcl_graph_denoise/graph_tikhonov_smoothing.h>
#include <pcl_graph_denoise/graph_tv_smoothing.h>

#include <pcl/common/io.h>
#include <pcl_conversions/pcl_conversions.h>
#include <ros/ros.h>
#include <sensor_msgs/PointCloud2.h>
#include <xmlrpcpp/XmlRpcValue.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <limits>
#include <map>
#include <memory>
#include <new>
#include <set>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

namespace {

using Cloud = pcl::PointCloud<pcl::PointXYZ>;
using Value = XmlRpc::XmlRpcValue;
using pcl_graph_denoise::tools::StepKind;
using pcl_graph_denoise::tools::XyzFields;
using pcl_graph_denoise::tools::countFinite;
using pcl_graph_denoise::tools::megabytesToBytes;
using pcl_graph_denoise::tools::stepClass;
using pcl_graph_denoise::tools::stepName;

/** A parameter error, reported at start-up. */
struct ConfigError : std::runtime_error
{
  using std::runtime_error::runtime_error;
};

/** A cloud that cannot be filtered, reported with ROS_ERROR. */
struct CloudError : std::runtime_error
{
  using std::runtime_error::runtime_error;
};

/** The parameters each kind of step takes: the command-line tool's step options. */
const std::set<std::string> &
parameterNames (StepKind kind)
{
  static const std::set<std::string> outliers = {
      "radius", "sigma", "threshold_ratio", "degree_threshold", "outlier_fraction",
      "residual_threshold", "keep_sparse_surfaces", "keep_organized", "threads", "memory_limit"};
  static const std::set<std::string> tikhonov = {
      "k", "sigma", "gamma", "graph_iterations", "normal_displacement", "local_surface",
      "adaptive_support", "patch_cover", "shrinkage_correction", "density_normalization", "tolerance", "max_iterations", "solver", "threads",
      "memory_limit"};
  static const std::set<std::string> tv = {
      "k", "sigma", "gamma", "graph_iterations", "normal_displacement", "local_surface",
      "adaptive_support", "patch_cover", "shrinkage_correction", "density_normalization", "tolerance", "max_iterations", "norm", "threads",
      "memory_limit"};
  switch (kind)
  {
  case StepKind::OUTLIERS:
    return outliers;
  case StepKind::TIKHONOV:
    return tikhonov;
  case StepKind::TV:
  case StepKind::TEMPORAL:  // not a step of the node (parseKind refuses it)
    break;
  }
  return tv;
}

/** A parameter value as given, for messages. */
std::string
describe (const Value &given)
{
  Value &v = const_cast<Value &> (given);  // XmlRpcValue's accessors are not const
  std::ostringstream text;
  switch (v.getType ())
  {
  case Value::TypeBoolean:
    text << (static_cast<bool> (v) ? "true" : "false");
    break;
  case Value::TypeInt:
    text << static_cast<int> (v);
    break;
  case Value::TypeDouble:
    text << static_cast<double> (v);
    break;
  case Value::TypeString:
    text << "'" << static_cast<std::string> (v) << "'";
    break;
  case Value::TypeArray:
    text << "a list";
    break;
  case Value::TypeStruct:
    text << "a dictionary";
    break;
  default:
    text << "a value of another type";
  }
  return text.str ();
}

/** One parameter of one step, with where it was set (for messages). */
struct Parameter
{
  std::string where;  // e.g. "~tv/gamma"
  Value value;
};

using Parameters = std::map<std::string, Parameter>;

ConfigError
invalid (const Parameter &p, const std::string &expected)
{
  return ConfigError (p.where + ": expected " + expected + ", got " + describe (p.value));
}

double
number (const Parameter &p, double minimum, double maximum, const std::string &expected)
{
  Value &v = const_cast<Value &> (p.value);
  double x;
  if (v.getType () == Value::TypeInt)
    x = static_cast<int> (v);
  else if (v.getType () == Value::TypeDouble)
    x = static_cast<double> (v);
  else
    throw invalid (p, expected);
  if (!std::isfinite (x) || x < minimum || x > maximum)
    throw invalid (p, expected);
  return x;
}

/** A number that must be > 0. */
double
positive (const Parameter &p)
{
  const double x = number (p, 0.0, std::numeric_limits<double>::max (), "a number > 0");
  if (!(x > 0.0))
    throw invalid (p, "a number > 0");
  return x;
}

int
integer (const Parameter &p, int minimum, const std::string &expected,
         int maximum = std::numeric_limits<int>::max ())
{
  Value &v = const_cast<Value &> (p.value);
  if (v.getType () != Value::TypeInt || static_cast<int> (v) < minimum ||
      static_cast<int> (v) > maximum)
    throw invalid (p, expected);
  return static_cast<int> (v);
}

bool
boolean (const Parameter &p)
{
  Value &v = const_cast<Value &> (p.value);
  if (v.getType () == Value::TypeBoolean)
    return static_cast<bool> (v);
  if (v.getType () == Value::TypeInt && (static_cast<int> (v) == 0 || static_cast<int> (v) == 1))
    return static_cast<int> (v) == 1;
  throw invalid (p, "true or false");
}

std::string
text (const Parameter &p, const std::set<std::string> &allowed)
{
  Value &v = const_cast<Value &> (p.value);
  std::string expected;
  for (const auto &a : allowed)
    expected += (expected.empty () ? "'" : " or '") + a + "'";
  if (v.getType () != Value::TypeString || !allowed.count (static_cast<std::string> (v)))
    throw invalid (p, expected);
  return static_cast<std::string> (v);
}

/** One step of the chain: a configured filter, kept from one cloud to the next. */
struct Step
{
  StepKind kind = StepKind::TV;
  std::string name;        // "step 2/2 (tv)", for messages
  std::string parameters;  // "gamma 0.004, k 12", for the start-up report
  bool keep_organized = false;
  std::unique_ptr<pcl_graph_denoise::GraphDegreeOutlierRemoval<pcl::PointXYZ>> outliers;
  std::unique_ptr<pcl_graph_denoise::GraphTikhonovSmoothing<pcl::PointXYZ>> tikhonov;
  std::unique_ptr<pcl_graph_denoise::GraphTVSmoothing<pcl::PointXYZ>> tv;

  pcl_graph_denoise::GraphSmoothing<pcl::PointXYZ> &
  smoother ()
  {
    if (tikhonov)
      return *tikhonov;
    return *tv;
  }
};

void
configureSmoother (pcl_graph_denoise::GraphSmoothing<pcl::PointXYZ> &filter,
                   const Parameters &parameters)
{
  for (const auto &[name, p] : parameters)
  {
    if (name == "k")
      filter.setKSearch (integer (p, 1, "an integer >= 1"));
    else if (name == "sigma")
      filter.setSigma (number (p, 0.0, std::numeric_limits<double>::max (), "a number >= 0"));
    else if (name == "gamma")
    {
      Value &v = const_cast<Value &> (p.value);
      if (v.getType () == Value::TypeString && static_cast<std::string> (v) == "auto")
        filter.setAutomaticGamma ();
      else
        filter.setGamma (
            number (p, 0.0, std::numeric_limits<double>::max (), "a number >= 0 or 'auto'"));
    }
    else if (name == "graph_iterations")
      filter.setGraphIterations (
          integer (p, 1,
                   "an integer in [1, " + std::to_string (pcl_graph_denoise::kMaxGraphIterations) +
                       "]",
                   pcl_graph_denoise::kMaxGraphIterations));
    else if (name == "normal_displacement")
      filter.setNormalDisplacement (boolean (p));
    else if (name == "local_surface")
    {
      pcl_graph_denoise::LocalSurface surface = filter.getLocalSurface ();
      pcl_graph_denoise::tools::localSurfaceFromName (text (p, {"plane", "quadric", "blended"}), surface);
      filter.setLocalSurface (surface);
    }
    else if (name == "adaptive_support")
      filter.setAdaptiveSupport (boolean (p));
    else if (name == "patch_cover")
      filter.setPatchCover (integer (p, 0, "an integer >= 0 (0 = a quadric at every point)"));
    else if (name == "shrinkage_correction")
      filter.setShrinkageCorrection (boolean (p));
    else if (name == "density_normalization")
      filter.setDensityNormalization (boolean (p));
    else if (name == "tolerance")
      filter.setTolerance (positive (p));
    else if (name == "max_iterations")
      filter.setMaximumIterations (integer (p, 1, "an integer >= 1"));
    else if (name == "threads")
      filter.setNumberOfThreads (integer (p, 0, "an integer >= 0 (0 = all cores)"));
    else if (name == "memory_limit")
      filter.setMemoryLimit (megabytesToBytes (number (
          p, 0.0, std::numeric_limits<double>::max (), "megabytes >= 0 (0 = this machine's memory)")));
  }
}

Step
makeStep (StepKind kind, const Parameters &parameters)
{
  Step step;
  step.kind = kind;
  for (const auto &[name, p] : parameters)
    step.parameters += (step.parameters.empty () ? "" : ", ") + name + " " + describe (p.value);
  if (step.parameters.empty ())
    step.parameters = "none, the filter's defaults";

  if (kind == StepKind::OUTLIERS)
  {
    step.outliers =
        std::make_unique<pcl_graph_denoise::GraphDegreeOutlierRemoval<pcl::PointXYZ>> (true);
    auto &filter = *step.outliers;
    int rules = 0;
    for (const auto &[name, p] : parameters)
    {
      const double max = std::numeric_limits<double>::max ();
      if (name == "radius")
        filter.setRadiusSearch (number (p, 0.0, max, "a number >= 0 (0 = derived)"));
      else if (name == "sigma")
        filter.setSigma (number (p, 0.0, max, "a number >= 0 (0 = derived)"));
      else if (name == "threshold_ratio")
      {
        filter.setAutomaticThresholdRatio (number (p, 0.0, max, "a number >= 0"));
        ++rules;
      }
      else if (name == "degree_threshold")
      {
        filter.setDegreeThreshold (number (p, 0.0, max, "a number >= 0"));
        ++rules;
      }
      else if (name == "outlier_fraction")
      {
        filter.setOutlierFraction (number (p, 0.0, 1.0, "a number in [0, 1]"));
        ++rules;
      }
      else if (name == "residual_threshold")
        filter.setResidualThreshold (number (p, 0.0, max, "a number >= 0 (0 = off)"));
      else if (name == "keep_sparse_surfaces")
        filter.setKeepSparseSurfaces (boolean (p));
      else if (name == "keep_organized")
        step.keep_organized = boolean (p);
      else if (name == "threads")
        filter.setNumberOfThreads (integer (p, 0, "an integer >= 0 (0 = all cores)"));
      else if (name == "memory_limit")
        filter.setMemoryLimit (
            megabytesToBytes (number (p, 0.0, max, "megabytes >= 0 (0 = this machine's memory)")));
    }
    if (rules > 1)
      throw ConfigError ("outliers: give at most one of threshold_ratio, degree_threshold and "
                         "outlier_fraction (got " + step.parameters + ")");
    return step;
  }

  if (kind == StepKind::TIKHONOV)
  {
    step.tikhonov = std::make_unique<pcl_graph_denoise::GraphTikhonovSmoothing<pcl::PointXYZ>> ();
    const auto solver = parameters.find ("solver");
    if (solver != parameters.end ())
      step.tikhonov->setSolver (text (solver->second, {"cg", "cholmod"}) == "cholmod"
                                    ? pcl_graph_denoise::core::TikhonovSolver::CHOLMOD
                                    : pcl_graph_denoise::core::TikhonovSolver::CONJUGATE_GRADIENT);
  }
  else
  {
    step.tv = std::make_unique<pcl_graph_denoise::GraphTVSmoothing<pcl::PointXYZ>> ();
    const auto norm = parameters.find ("norm");
    if (norm != parameters.end ())
      step.tv->setNorm (text (norm->second, {"isotropic", "anisotropic"}) == "anisotropic"
                            ? pcl_graph_denoise::core::TotalVariationNorm::ANISOTROPIC
                            : pcl_graph_denoise::core::TotalVariationNorm::ISOTROPIC);
  }
  configureSmoother (step.smoother (), parameters);
  return step;
}

StepKind
parseKind (const std::string &name, const std::string &where)
{
  for (const StepKind kind : {StepKind::OUTLIERS, StepKind::TIKHONOV, StepKind::TV})
    if (name == stepName (kind))
      return kind;
  throw ConfigError (where + ": unknown step '" + name +
                     "' (steps: 'outliers', 'tikhonov', 'tv')");
}

/** Adds the entries of a dictionary of parameters for a step of `kind`, those already
 *  there (from a more specific place) winning. Unknown names are errors. */
void
addParameters (Parameters &parameters, const Value &given, const std::string &where,
               StepKind kind, const std::set<std::string> &ignored = {})
{
  Value &dict = const_cast<Value &> (given);
  if (dict.getType () != Value::TypeStruct)
    throw ConfigError (where + ": expected a dictionary of parameters, got " + describe (given));
  for (auto it = dict.begin (); it != dict.end (); ++it)
  {
    if (ignored.count (it->first))
      continue;
    if (!parameterNames (kind).count (it->first))
    {
      std::string names;
      for (const auto &n : parameterNames (kind))
        names += (names.empty () ? "" : ", ") + n;
      throw ConfigError (where + "/" + it->first + ": not a parameter of a '" + stepName (kind) +
                         "' step (" + names + ")");
    }
    if (!parameters.count (it->first))
      parameters[it->first] = Parameter{where + "/" + it->first, it->second};
  }
}

/**
 * Reads the chain from the private parameters:
 *   ~chain                 list of steps, each "outliers", "tikhonov" or "tv", or a
 *                          dictionary {step: tv, gamma: 0.004, ...}; also a string
 *                          "outliers, tv" (default: [outliers, tv])
 *   ~outliers/NAME, ~tikhonov/NAME, ~tv/NAME
 *                          parameters of every step of that kind
 *   ~NAME                  parameters of every step that has NAME
 * The most specific place wins: a step's dictionary, then its kind, then ~NAME. A
 * parameter not given anywhere keeps the filter's (data-derived) default.
 */
std::vector<Step>
readChain (const ros::NodeHandle &private_nh)
{
  Value all;
  if (!private_nh.getParam (private_nh.getNamespace (), all) ||
      all.getType () != Value::TypeStruct)
    all = Value ();
  const std::string ns = "~";
  const auto has = [&] (const std::string &key) {
    return all.getType () == Value::TypeStruct && all.hasMember (key);
  };

  // The chain: a list of names or dictionaries, or one string of names.
  struct Entry
  {
    StepKind kind;
    Value own;  // the step's own dictionary, or invalid
    std::string where;
  };
  std::vector<Entry> entries;
  const auto addName = [&] (const std::string &name, const std::string &where) {
    entries.push_back ({parseKind (name, where), Value (), where});
  };
  if (!has ("chain"))
  {
    addName ("outliers", "default chain");
    addName ("tv", "default chain");
  }
  else
  {
    Value &chain = all["chain"];
    if (chain.getType () == Value::TypeString)
    {
      std::string names = static_cast<std::string> (chain);
      for (auto &c : names)
        if (c == ',' || c == '[' || c == ']')
          c = ' ';
      std::istringstream words (names);
      for (std::string word; words >> word;)
        addName (word, ns + "chain");
    }
    else if (chain.getType () == Value::TypeArray)
    {
      for (int i = 0; i < chain.size (); ++i)
      {
        const std::string where = ns + "chain[" + std::to_string (i) + "]";
        Value &entry = chain[i];
        if (entry.getType () == Value::TypeString)
          addName (static_cast<std::string> (entry), where);
        else if (entry.getType () == Value::TypeStruct && entry.hasMember ("step") &&
                 entry["step"].getType () == Value::TypeString)
          entries.push_back (
              {parseKind (static_cast<std::string> (entry["step"]), where), entry, where});
        else
          throw ConfigError (where + ": expected a step name or a dictionary with a 'step' "
                             "name, got " + describe (entry));
      }
    }
    else
      throw ConfigError (ns + "chain: expected a list of steps, got " + describe (chain));
    if (entries.empty ())
      throw ConfigError (ns + "chain: no step (steps: 'outliers', 'tikhonov', 'tv')");
  }

  // Private parameters that name no step parameter are probably typos.
  static const std::set<std::string> own = {"chain", "queue_size", "outliers", "tikhonov", "tv"};
  if (all.getType () == Value::TypeStruct)
    for (auto it = all.begin (); it != all.end (); ++it)
      if (!own.count (it->first) && !parameterNames (StepKind::OUTLIERS).count (it->first) &&
          !parameterNames (StepKind::TIKHONOV).count (it->first) &&
          !parameterNames (StepKind::TV).count (it->first))
        throw ConfigError (ns + it->first + ": not a parameter of this node (see docs/ros.md)");
  for (const StepKind kind : {StepKind::OUTLIERS, StepKind::TIKHONOV, StepKind::TV})
    if (has (stepName (kind)))
    {
      Parameters checked;  // also where no step of that kind is in the chain
      addParameters (checked, all[stepName (kind)], ns + stepName (kind), kind);
    }

  std::vector<Step> steps;
  for (std::size_t s = 0; s < entries.size (); ++s)
  {
    const Entry &entry = entries[s];
    const StepKind kind = entry.kind;
    Parameters parameters;
    if (entry.own.valid ())
      addParameters (parameters, entry.own, entry.where, kind, {"step"});
    if (has (stepName (kind)))
      addParameters (parameters, all[stepName (kind)], ns + stepName (kind), kind);
    for (const auto &name : parameterNames (kind))
      if (has (name) && !parameters.count (name))
        parameters[name] = Parameter{ns + name, all[name]};
    steps.push_back (makeStep (kind, parameters));
    steps.back ().name = "step " + std::to_string (s + 1) + "/" + std::to_string (entries.size ()) +
                         " (" + stepName (kind) + ")";
  }
  return steps;
}

/** Checks that the layout a PointCloud2 announces fits its data, so that reading a
 *  point never leaves the buffer. Throws CloudError. */
void
checkLayout (const sensor_msgs::PointCloud2 &msg)
{
  const std::uint64_t points = std::uint64_t (msg.width) * msg.height;
  if (points == 0)
    throw CloudError ("the cloud is empty");
  if (msg.is_bigendian)
    throw CloudError ("big-endian point data is not supported");
  if (msg.point_step == 0)
    throw CloudError ("inconsistent layout: point_step 0");
  if (std::uint64_t (msg.row_step) < std::uint64_t (msg.width) * msg.point_step)
    throw CloudError ("inconsistent layout: row_step " + std::to_string (msg.row_step) +
                      " < width " + std::to_string (msg.width) + " x point_step " +
                      std::to_string (msg.point_step));
  const std::uint64_t needed = std::uint64_t (msg.row_step) * msg.height;
  if (msg.data.size () < needed)
    throw CloudError ("truncated: " + std::to_string (msg.data.size ()) +
                      " bytes of data for the " + std::to_string (needed) +
                      " bytes that width, height and row_step announce");
  for (const auto &field : msg.fields)
  {
    const std::uint64_t size = pcl::getFieldSize (field.datatype);
    const std::uint64_t end =
        std::uint64_t (field.offset) + size * std::max<std::uint32_t> (field.count, 1);
    if (size == 0 || end > msg.point_step)
      throw CloudError ("field '" + field.name + "' (offset " + std::to_string (field.offset) +
                        ", datatype " + std::to_string (field.datatype) + ", count " +
                        std::to_string (field.count) + ") does not fit in point_step " +
                        std::to_string (msg.point_step));
  }
}

class DenoiseNode
{
public:
  DenoiseNode (ros::NodeHandle &nh, ros::NodeHandle &private_nh) : steps_ (readChain (private_nh))
  {
    int queue_size = 1;
    private_nh.param ("queue_size", queue_size, queue_size);
    if (queue_size < 1)
      throw ConfigError ("~queue_size: expected an integer >= 1, got " +
                         std::to_string (queue_size));
    for (const auto &step : steps_)
      ROS_INFO ("%s: %s, parameters set: %s", step.name.c_str (), stepClass (step.kind),
                step.parameters.c_str ());
    publisher_ = nh.advertise<sensor_msgs::PointCloud2> ("output", 1);
    subscriber_ = nh.subscribe ("input", static_cast<std::uint32_t> (queue_size),
                                &DenoiseNode::onCloud, this);
    ROS_INFO ("denoising %s into %s", subscriber_.getTopic ().c_str (),
              publisher_.getTopic ().c_str ());
  }

private:
  void
  onCloud (const sensor_msgs::PointCloud2ConstPtr &msg)
  {
    const auto start = std::chrono::steady_clock::now ();
    const std::size_t size_in = std::size_t (msg->width) * msg->height;
    try
    {
      sensor_msgs::PointCloud2 out;
      const std::string report = denoise (*msg, out);
      const double ms =
          std::chrono::duration<double, std::milli> (std::chrono::steady_clock::now () - start)
              .count ();
      ROS_INFO_ONCE ("first cloud: %zu -> %u points in %.1f ms (%s)", size_in,
                     out.width * out.height, ms, report.c_str ());
      ROS_DEBUG ("%zu -> %u points in %.1f ms (%s)", size_in, out.width * out.height, ms,
                 report.c_str ());
      publisher_.publish (out);
      return;
    }
    catch (const std::bad_alloc &)
    {
      reject (*msg, "out of memory");
    }
    catch (const std::exception &e)  // CloudError, tools::Error (no x, y or z), ros::Exception
    {
      reject (*msg, e.what ());
    }
  }

  static void
  reject (const sensor_msgs::PointCloud2 &msg, const char *why)
  {
    ROS_ERROR ("cloud of %u x %u points (frame '%s', stamp %u.%09u) not denoised, nothing "
               "published: %s",
               msg.width, msg.height, msg.header.frame_id.c_str (), msg.header.stamp.sec,
               msg.header.stamp.nsec, why);
  }

  /** Runs the chain on `msg` into `out`; returns a one-line report. Throws on failure. */
  std::string
  denoise (const sensor_msgs::PointCloud2 &msg, sensor_msgs::PointCloud2 &out)
  {
    checkLayout (msg);
    pcl::PCLPointCloud2 cloud;
    pcl_conversions::toPCL (msg, cloud);
    XyzFields xyz (cloud, "input cloud");
    xyz.centreOn (cloud);  // geo-referenced double coordinates keep their precision
    if (countFinite (*xyz.extract (cloud)) == 0)
      throw CloudError ("no point has a finite x, y, z");

    std::string report;
    for (auto &step : steps_)
    {
      report += report.empty () ? "" : ", ";
      // Outlier removal may have removed every point (or set them all to NaN).
      if (countFinite (*xyz.extract (cloud)) == 0)
        report += step.name + " skipped: no point left";
      else if (step.kind == StepKind::OUTLIERS)
        report += removeOutliers (step, xyz, cloud);
      else
        report += smooth (step, xyz, cloud);
    }
    if (countFinite (*xyz.extract (cloud)) == 0)
      ROS_WARN_THROTTLE (10.0, "every point was removed as an outlier: publishing %s",
                         cloud.width * cloud.height == 0 ? "an empty cloud"
                                                         : "a cloud of NaN points");

    cloud.is_dense = cloud.width * cloud.height == 0 || xyz.extract (cloud)->is_dense;
    pcl_conversions::fromPCL (cloud, out);
    out.header = msg.header;  // PCL's header keeps microseconds only: keep the exact stamp
    return report;
  }

  static std::string
  removeOutliers (Step &step, const XyzFields &xyz, pcl::PCLPointCloud2 &cloud)
  {
    auto &filter = *step.outliers;
    const Cloud::Ptr input = xyz.extract (cloud);
    filter.setInputCloud (input);
    pcl::Indices kept;
    filter.filter (kept);
    filter.setInputCloud (Cloud::ConstPtr ());  // do not hold the cloud until the next one
    const pcl::Indices &gone = *filter.getRemovedIndices ();
    if (kept.size () + gone.size () != input->size ())
      throw CloudError (step.name + " failed (see the PCL error above)");
    if (step.keep_organized)
      for (const auto index : gone)
        xyz.setNaN (cloud, static_cast<std::size_t> (index));
    else
      cloud = pcl_graph_denoise::tools::selectPoints (cloud, kept);
    return step.name + ": " + std::to_string (gone.size ()) + " removed";
  }

  static std::string
  smooth (Step &step, const XyzFields &xyz, pcl::PCLPointCloud2 &cloud)
  {
    auto &filter = step.smoother ();
    const Cloud::Ptr input = xyz.extract (cloud);
    if (countFinite (*input) == 0)
      throw CloudError (step.name + ": no point with a finite x, y, z is left to smooth");
    filter.setInputCloud (input);
    Cloud output;
    filter.filter (output);
    filter.setInputCloud (Cloud::ConstPtr ());
    if (output.size () != input->size ())
      throw CloudError (step.name + " failed (see the PCL error above)");
    const std::size_t moved = xyz.writeBack (cloud, *input, output);
    char used[128];
    std::snprintf (used, sizeof (used), "%zu moved, gamma %g, %d solver iterations", moved,
                   filter.getUsedGamma (), filter.getSolverReport ().iterations);
    return step.name + ": " + used;
  }

  std::vector<Step> steps_;
  ros::Publisher publisher_;
  ros::Subscriber subscriber_;
};

}  // namespace

int
main (int argc, char **argv)
{
  ros::init (argc, argv, "pcl_graph_denoise");
  ros::NodeHandle nh, private_nh ("~");
  try
  {
    DenoiseNode node (nh, private_nh);
    ros::spin ();
  }
  catch (const ConfigError &e)
  {
    ROS_FATAL ("invalid parameter: %s", e.what ());
    return 1;
  }
  catch (const std::exception &e)  // e.g. ros::InvalidNameException for a bad remapping
  {
    ROS_FATAL ("%s", e.what ());
    return 1;
  }
  return 0;
}

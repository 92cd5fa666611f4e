/*
 * pcl_graph_denoise: graph-signal-processing point cloud denoising for PCL.
 * SPDX-License-Identifier: BSD-3-Clause
 */
#pragma once

#include "steps.h"

#include <map>
#include <stdexcept>
#include <string>
#include <vector>

namespace pcl_graph_denoise {
namespace tools {

/** \brief A command-line error: one line on stderr and exit code 2. */
struct UsageError : std::runtime_error
{
  using std::runtime_error::runtime_error;
};

/** \brief A step parameter as given on the command line, already checked: `number`
 *  for numbers and switches (0 or 1), `text` for the named choices ("auto" for gamma,
 *  "cg", "isotropic"...). */
struct ParameterValue
{
  double number = 0.0;
  std::string text;
};

/** \brief One step of the chain and the parameters set for it (those given after it,
 *  and those given before the first step that it has); a parameter not set keeps the
 *  filter's own, data-derived default. */
struct Step
{
  StepKind kind;
  std::map<std::string, ParameterValue> parameters;

  /** \brief True when the parameter was given for this step. */
  bool
  has (const std::string &name) const
  {
    return parameters.count (name) > 0;
  }
};

/** \brief Everything the command line asks for. */
struct Options
{
  bool help = false;
  std::string input, output;  ///< the first input and its output
  /** Every input, in time order with -temporal (else the one input), and where each
   *  result goes (with -temporal: the output folder / the input's file name). */
  std::vector<std::string> inputs, outputs;
  std::string removed;  ///< where the removed points go; empty: nowhere
  bool binary = true;
  bool quiet = false;
  bool default_chain = false;  ///< no step was given: -outliers -tv
  std::vector<Step> steps;
};

/** \brief Parses the command line.
 *  \throws UsageError with a one-line message. */
Options
parseCommandLine (int argc, const char *const *argv);

/** \brief The text of -h: every option with its default (the defaults are read from
 *  default-constructed filters). */
std::string
usage (const std::string &program);

}  // namespace tools
}  // namespace pcl_graph_denoise

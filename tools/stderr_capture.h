/*
 * pcl_graph_denoise: graph-signal-processing point cloud denoising for PCL.
 * SPDX-License-Identifier: BSD-3-Clause
 */
#pragma once

#include <cstdio>
#include <string>

namespace pcl_graph_denoise {
namespace tools {

/** \brief Holds back what is written to stderr (file descriptor 2) while it lives.
 *
 * PCL's readers and the filters report through PCL_ERROR / PCL_WARN on stderr, often
 * several lines for one problem (and PCL's PLY reader one line per property it does not
 * handle, also on valid files). The tool runs them under a capture, then either folds the
 * message that matters into its own one-line error, or passes the text on.
 */
class StderrCapture
{
public:
  /** \brief Starts capturing; when that is impossible, stderr is left alone. */
  StderrCapture ();

  /** \brief Stops capturing; what was captured and not taken by release() is lost. */
  ~StderrCapture ();

  StderrCapture (const StderrCapture &) = delete;
  StderrCapture &
  operator= (const StderrCapture &) = delete;

  /** \brief Stops capturing (if not done yet) and returns the captured text. */
  std::string
  release ();

  /** \brief Writes `text` to the real stderr at once, also while capturing (progress
   *  reports during a filter's run). */
  void
  writeThrough (const std::string &text) const;

private:
  std::FILE *file_ = nullptr;
  int saved_fd_ = -1;
};

/** \brief The most telling line of messages captured from PCL, without its
 *  "[pcl::Class::method] " tag and with control characters replaced; empty if none.
 *  Lines known to be noise (properties PCL does not handle, lines it ignores, the
 *  generic "problem parsing header") are skipped. */
std::string
mainMessage (const std::string &captured);

/** \brief A string made fit for a one-line message: control characters become '?' and
 *  it is cut to max_length characters (with "..."). */
std::string
printable (const std::string &text, std::size_t max_length = 200);

}  // namespace tools
}  // namespace pcl_graph_denoise

/*
 * pcl_graph_denoise: graph-signal-processing point cloud denoising for PCL.
 * SPDX-License-Identifier: BSD-3-Clause
 *
 * The steps a chain can run and their names, shared by the command-line tool and the
 * ROS node (examples/ros/pcl_graph_denoise_ros), which compiles this header alone.
 */
#pragma once

#include <pcl_graph_denoise/graph_smoothing.h>

#include <cstddef>
#include <limits>
#include <string>

namespace pcl_graph_denoise {
namespace tools {

/** \brief The filters a step can run. */
enum class StepKind
{
  OUTLIERS,  ///< GraphDegreeOutlierRemoval
  TIKHONOV,  ///< GraphTikhonovSmoothing
  TV,        ///< GraphTVSmoothing
  TEMPORAL   ///< GraphSequenceSmoothing over several inputs (command-line tool only)
};

/** \brief The option naming a step ("-outliers", "-tikhonov", "-tv"); without its
 *  leading '-', the step's name in a ROS parameter ("outliers", ...). */
inline const char *
stepOption (StepKind kind)
{
  switch (kind)
  {
  case StepKind::OUTLIERS:
    return "-outliers";
  case StepKind::TIKHONOV:
    return "-tikhonov";
  case StepKind::TEMPORAL:
    return "-temporal";
  case StepKind::TV:
    break;
  }
  return "-tv";
}

/** \brief The step's name without the option's '-' ("outliers", "tikhonov", "tv"). */
inline const char *
stepName (StepKind kind)
{
  return stepOption (kind) + 1;
}

/** \brief The class a step runs ("GraphDegreeOutlierRemoval", ...). */
inline const char *
stepClass (StepKind kind)
{
  switch (kind)
  {
  case StepKind::OUTLIERS:
    return "GraphDegreeOutlierRemoval";
  case StepKind::TIKHONOV:
    return "GraphTikhonovSmoothing";
  case StepKind::TEMPORAL:
    return "GraphSequenceSmoothing";
  case StepKind::TV:
    break;
  }
  return "GraphTVSmoothing";
}

/** \brief A memory_limit given in megabytes (10^6 bytes) in bytes, saturated at the
 *  largest std::size_t; 0 stays 0 (the filters' "this machine's memory"). */
inline std::size_t
megabytesToBytes (double megabytes)
{
  const double bytes = megabytes * 1e6;
  return bytes >= double (std::numeric_limits<std::size_t>::max ())
             ? std::numeric_limits<std::size_t>::max ()
             : static_cast<std::size_t> (bytes);
}

/** \brief The name of a local surface in an option or parameter value ("plane",
 *  "quadric", "blended"). */
inline const char *
localSurfaceName (LocalSurface surface)
{
  switch (surface)
  {
  case LocalSurface::PLANE:
    return "plane";
  case LocalSurface::QUADRIC:
    return "quadric";
  case LocalSurface::BLENDED_QUADRICS:
    break;
  }
  return "blended";
}

/** \brief The local surface named `name` (localSurfaceName); false for another name. */
inline bool
localSurfaceFromName (const std::string &name, LocalSurface &surface)
{
  for (const LocalSurface s : {LocalSurface::PLANE, LocalSurface::QUADRIC, LocalSurface::BLENDED_QUADRICS})
    if (name == localSurfaceName (s))
    {
      surface = s;
      return true;
    }
  return false;
}

}  // namespace tools
}  // namespace pcl_graph_denoise

/*
 * pcl_graph_denoise: graph-signal-processing point cloud denoising for PCL.
 * SPDX-License-Identifier: BSD-3-Clause
 */
#pragma once

#include <pcl_graph_denoise/core/normals.h>
#include <pcl_graph_denoise/graph_sequence_smoothing.h>
#include <pcl_graph_denoise/point_cloud_adaptor.h>

#include <pcl/console/print.h>

#include <algorithm>
#include <exception>
#include <numeric>

namespace pcl_graph_denoise {

template <typename PointT>
std::string
GraphSequenceSmoothing<PointT>::invalidParameters () const
{
  if (!smoother_)
    return "smoother (setSmoother): must not be null";
  if (k_temporal_ < 0)
    return "k2 (setKTemporal) = " + std::to_string (k_temporal_) + ": must be >= 0";
  if (window_ < 0)
    return "window (setTemporalWindow) = " + std::to_string (window_) + ": must be >= 0";
  const std::string smoother = smoother_->invalidParameters ();
  return smoother.empty () ? smoother : "smoother's " + smoother;
}

template <typename PointT>
bool
GraphSequenceSmoothing<PointT>::filter (const std::vector<PointCloudPtr> &frames,
                                        std::vector<PointCloudPtr> &output)
{
  return filter (std::vector<PointCloudConstPtr> (frames.begin (), frames.end ()), output);
}

template <typename PointT>
bool
GraphSequenceSmoothing<PointT>::filter (const std::vector<PointCloudConstPtr> &frames,
                                        std::vector<PointCloudPtr> &output)
{
  output.clear ();
  std::string invalid = invalidParameters ();
  for (std::size_t t = 0; t < frames.size () && invalid.empty (); ++t)
    if (!frames[t])
      invalid = "frame " + std::to_string (t) + ": null pointer";
  if (!invalid.empty ())
  {
    PCL_ERROR ("[pcl_graph_denoise::GraphSequenceSmoothing::filter] Invalid %s.\n",
               invalid.c_str ());
    return false;
  }
  const std::size_t w = static_cast<std::size_t> (window_);
  std::vector<PointCloudPtr> result (frames.size ());
  for (std::size_t t = 0; t < frames.size (); ++t)
  {
    const std::size_t first = t >= w ? t - w : 0;
    const std::size_t last = std::min (frames.size () - 1, t + w);
    const std::vector<PointCloudConstPtr> window (frames.begin () + first, frames.begin () + last + 1);
    if (!denoiseFrame (window, t - first, result[t]))
      return false;
  }
  output.swap (result);
  return true;
}

template <typename PointT>
std::vector<typename GraphSequenceSmoothing<PointT>::PointCloudConstPtr>
GraphSequenceSmoothing<PointT>::heldWindow (std::size_t t, std::size_t &centre) const
{
  const std::size_t w = static_cast<std::size_t> (window_);
  const std::size_t first = std::max (first_held_, t >= w ? t - w : 0);
  const std::size_t last = std::min (pushed_ - 1, t + w);
  centre = t - first;
  return std::vector<PointCloudConstPtr> (held_.begin () + (first - first_held_),
                                          held_.begin () + (last - first_held_ + 1));
}

template <typename PointT>
bool
GraphSequenceSmoothing<PointT>::push (const PointCloudConstPtr &frame, PointCloudPtr &denoised)
{
  denoised.reset ();
  std::string invalid = invalidParameters ();
  if (invalid.empty () && !frame)
    invalid = "frame " + std::to_string (pushed_) + ": null pointer";
  if (!invalid.empty ())
  {
    PCL_ERROR ("[pcl_graph_denoise::GraphSequenceSmoothing::push] Invalid %s; the frame is "
               "not added.\n", invalid.c_str ());
    return false;
  }
  held_.push_back (frame);
  ++pushed_;
  const std::size_t w = static_cast<std::size_t> (window_);
  bool ok = true;
  if (pushed_ - next_output_ > w)
  {
    std::size_t centre = 0;
    const std::vector<PointCloudConstPtr> window = heldWindow (next_output_, centre);
    ok = denoiseFrame (window, centre, denoised);
    ++next_output_;
  }
  // Keep only the frames a later window needs: next_output_ - window onwards (the
  // window may have been changed between pushes; never drop a pending frame).
  const std::size_t keep_from = next_output_ >= w ? next_output_ - w : 0;
  while (first_held_ < keep_from && !held_.empty ())
  {
    held_.pop_front ();
    ++first_held_;
  }
  return ok;
}

template <typename PointT>
bool
GraphSequenceSmoothing<PointT>::flush (std::vector<PointCloudPtr> &denoised)
{
  denoised.clear ();
  const std::string invalid = invalidParameters ();
  if (!invalid.empty ())
  {
    PCL_ERROR ("[pcl_graph_denoise::GraphSequenceSmoothing::flush] Invalid %s; the frames "
               "are kept.\n", invalid.c_str ());
    return false;
  }
  bool ok = true;
  for (; next_output_ < pushed_ && ok; ++next_output_)
  {
    std::size_t centre = 0;
    const std::vector<PointCloudConstPtr> window = heldWindow (next_output_, centre);
    PointCloudPtr frame;
    ok = denoiseFrame (window, centre, frame);
    if (ok)
      denoised.push_back (frame);
  }
  reset ();
  return ok;
}

template <typename PointT>
void
GraphSequenceSmoothing<PointT>::reset ()
{
  held_.clear ();
  first_held_ = pushed_ = next_output_ = 0;
}

template <typename PointT>
bool
GraphSequenceSmoothing<PointT>::denoiseFrame (const std::vector<PointCloudConstPtr> &window_frames,
                                              std::size_t centre, PointCloudPtr &output)
{
  static const char *const kName = "GraphSequenceSmoothing";
  const PointCloud &frame = *window_frames[centre];
  Smoother &smoother = *smoother_;
  if (frame.empty ())
  {
    output.reset (new PointCloud (frame));
    return true;
  }
  // Only the centre frame with k2 = 0 or a window of one frame: the static filter itself.
  if (k_temporal_ == 0 || window_ == 0 || window_frames.size () == 1)
  {
    // On the whole frame; the caller's own input cloud and indices of the smoother are
    // put back afterwards (they were cleared), also when the call throws.
    struct Restore
    {
      Smoother &s;
      PointCloudConstPtr input;
      pcl::IndicesPtr indices;
      bool use_indices, fake_indices;
      ~Restore ()
      {
        s.input_ = input;
        s.indices_ = indices;
        s.use_indices_ = use_indices;
        s.fake_indices_ = fake_indices;
      }
    } restore{smoother, smoother.input_, smoother.indices_, smoother.use_indices_,
              smoother.fake_indices_};
    smoother.setInputCloud (window_frames[centre]);
    smoother.setIndices (pcl::IndicesPtr ());
    output.reset (new PointCloud);
    smoother.filter (*output);
    if (output->size () != frame.size ())
    {
      PCL_ERROR ("[pcl_graph_denoise::%s::filter] The smoothing of a frame of %zu points "
                 "failed.\n", kName, frame.size ());
      output.reset ();
      return false;
    }
    return true;
  }

  output.reset (new PointCloud (frame));
  smoother.used_gamma_ = smoother.used_sigma_ = smoother.estimated_noise_ = 0.0;
  smoother.report_ = core::SolverReport{};
  smoother.components_ = core::GraphComponents{};
  // Gather each frame's finite points, positions relative to the centre frame's mean;
  // a frame's exact copies are one vertex, as in the static filters.
  std::vector<GatheredPoints> gathered (window_frames.size ());
  std::vector<core::DistinctPoints> distinct (window_frames.size ());
  std::size_t total = 0, centre_row = 0;
  for (std::size_t f = 0; f < window_frames.size (); ++f)
  {
    pcl::Indices all (window_frames[f]->size ());
    std::iota (all.begin (), all.end (), 0);
    gathered[f] = gatherFinitePoints (*window_frames[f], all);
    distinct[f] = core::distinctPoints (gathered[f].xyz);
    if (f == centre)
      centre_row = total;
    total += gathered[f].cloud_index.size () - distinct[f].copies;
  }
  const GatheredPoints &own = gathered[centre];
  if (own.cloud_index.empty ())
  {
    PCL_WARN ("[pcl_graph_denoise::%s::filter] A frame of %zu points has no finite point; "
              "it is returned unchanged.\n", kName, frame.size ());
    return true;
  }
  if (!smoother.automatic_gamma_ && smoother.gamma_ == 0.0)
    return true;  // the identity

  std::vector<std::size_t> frame_rows;
  core::Signal3 start (static_cast<Eigen::Index> (total), 3);
  Eigen::Index row = 0;
  for (std::size_t f = 0; f < gathered.size (); ++f)
  {
    const Eigen::RowVector3d offset = (gathered[f].origin - own.origin).transpose ();
    const core::PointMatrix &points = distinct[f].copies > 0 ? distinct[f].points : gathered[f].xyz;
    frame_rows.push_back (static_cast<std::size_t> (points.rows ()));
    for (Eigen::Index r = 0; r < points.rows (); ++r, ++row)
      start.row (row) = points.row (r).template cast<double> () + offset;
  }

  if (motion_compensation_)
  {
    // Each other frame moved onto the centre frame's surface (in single precision for
    // the search, as every graph of the core; the offsets are added in double).
    const core::PointMatrix reference =
        start.middleRows (static_cast<Eigen::Index> (centre_row),
                          static_cast<Eigen::Index> (frame_rows[centre])).template cast<float> ();
    core::SurfaceOffsetParams offset_params;
    offset_params.num_threads = smoother.num_threads_;
    Eigen::Index first = 0;
    try
    {
      for (std::size_t f = 0; f < frame_rows.size (); ++f)
      {
        const auto rows = static_cast<Eigen::Index> (frame_rows[f]);
        if (f != centre && rows > 0)
          start.middleRows (first, rows) += core::surfaceOffsets (
              start.middleRows (first, rows).template cast<float> (), reference, offset_params);
        first += rows;
      }
    }
    catch (const std::exception &e)
    {
      PCL_ERROR ("[pcl_graph_denoise::%s::filter] %s.\n", kName, e.what ());
      output.reset ();
      return false;
    }
  }

  core::SpatioTemporalGraphParams params;
  params.k_spatial = smoother.k_;
  params.k_temporal = k_temporal_;
  params.window = window_;
  params.sigma = smoother.sigma_;
  params.num_threads = smoother.num_threads_;
  params.memory_limit = smoother.memory_limit_;
  core::Signal3 position;
  try
  {
    const std::size_t neighbours = std::size_t (smoother.k_) +
                                   std::size_t (k_temporal_) * (window_frames.size () - 1);
    core::requireMemory (smoother.estimateMemoryFor (total, neighbours), smoother.memory_limit_,
                         "smoothing a window of " + std::to_string (window_frames.size ()) +
                             " frames (" + std::to_string (total) + " points)",
                         "k, the temporal k or the window");
    position = smoother.runPasses (start, [&] (const core::PointMatrix &points) {
      std::vector<core::PointMatrix> frames;
      Eigen::Index first = 0;
      for (const std::size_t rows : frame_rows)
      {
        frames.emplace_back (points.middleRows (first, static_cast<Eigen::Index> (rows)));
        first += static_cast<Eigen::Index> (rows);
      }
      return core::buildSpatioTemporalGraph (frames, params);
    });
  }
  catch (const std::exception &e)
  {
    PCL_ERROR ("[pcl_graph_denoise::%s::filter] %s.\n", kName, e.what ());
    output.reset ();
    return false;
  }
  // The centre frame's rows, every copy from its position's vertex.
  const auto rows = static_cast<Eigen::Index> (own.cloud_index.size ());
  const auto first = static_cast<Eigen::Index> (centre_row);
  core::Signal3 own_start (rows, 3), own_position (rows, 3);
  for (Eigen::Index r = 0; r < rows; ++r)
  {
    const Eigen::Index v =
        first + static_cast<Eigen::Index> (distinct[centre].of_row[static_cast<std::size_t> (r)]);
    own_start.row (r) = start.row (v);
    own_position.row (r) = position.row (v);
  }
  if (!writeDisplacements (own.cloud_index, own_start, own_position, *output))
  {
    PCL_ERROR ("[pcl_graph_denoise::%s::filter] The smoothed positions overflowed: gamma = "
               "%g is too large.\n", kName, smoother.used_gamma_);
    output.reset ();
    return false;
  }
  return true;
}

} // namespace pcl_graph_denoise

#define PCL_INSTANTIATE_GraphSequenceSmoothing(T)                                            \
  template class pcl_graph_denoise::GraphSequenceSmoothing<T>;

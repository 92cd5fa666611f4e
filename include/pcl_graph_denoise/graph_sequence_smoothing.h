/*
 * pcl_graph_denoise: graph-signal-processing point cloud denoising for PCL.
 * SPDX-License-Identifier: BSD-3-Clause
 */
#pragma once

#include <pcl_graph_denoise/graph_smoothing.h>
#include <pcl_graph_denoise/graph_tikhonov_smoothing.h>

#include <pcl/point_cloud.h>

#include <deque>
#include <memory>
#include <string>
#include <vector>

namespace pcl_graph_denoise {

/** \brief Denoising of a time-varying point cloud on the paper's spatio-temporal graph:
 *  each point linked to its k1 nearest neighbours in its own frame and to its k2 nearest
 *  in each frame within +-window (core::buildSpatioTemporalGraph), then smoothed with
 *  Tikhonov or total variation exactly as the static filter does (same data-derived
 *  gamma, refinements and passes), so that the neighbouring frames' samples of the same
 *  surface average the noise away.
 *
 * The frames must be in one coordinate system (a fixed sensor, or registered first, for
 * instance with pcl::IterativeClosestPoint; see examples/sequence_registration.cpp).
 * Points do not correspond across frames; frames may differ in size; a frame may be
 * empty or hold non-finite points (they pass through unchanged and are never used).
 * A frame's exact copies of a point are one vertex, and every copy moves as one.
 *
 * Each frame t is denoised on the graph of the frames t - window ... t + window (those
 * that exist), and only frame t's points are kept from that solve. That makes the
 * streaming use (push(): frame t - window comes out once frame t has arrived; only the
 * frames of one window are held) give exactly the batch result (filter()). The cost per
 * frame is that of the static filter on the 2 window + 1 frames of its window.
 *
 * The smoothing itself is a configured GraphTikhonovSmoothing (default) or
 * GraphTVSmoothing (setSmoother): its k is k1, and its theta, gamma, refinements,
 * solver settings, threads and memory limit apply; its own input cloud and indices are
 * not used (each frame is smoothed whole) and are left as they were. With one frame,
 * or k2 = 0, or window = 0, each frame is denoised by that static filter on its own, bit
 * for bit.
 *
 * Output: one cloud per frame, a copy of the frame (size, order, organisation, header
 * and every field) in which only x, y, z of the finite points moved. Invalid parameters
 * or a null frame print a PCL_ERROR naming the class and the parameter, and the call
 * returns false with nothing produced; the input frames are never modified.
 *
 * \code
 * pcl_graph_denoise::GraphSequenceSmoothing<pcl::PointXYZ> sequence;
 * sequence.setKTemporal (3);
 * std::vector<pcl::PointCloud<pcl::PointXYZ>::Ptr> denoised;
 * sequence.filter (frames, denoised);   // or, live: sequence.push (frame, ready)
 * \endcode
 */
template <typename PointT>
class GraphSequenceSmoothing
{
public:
  using PointCloud = pcl::PointCloud<PointT>;                  ///< one frame
  using PointCloudPtr = typename PointCloud::Ptr;              ///< a denoised frame
  using PointCloudConstPtr = typename PointCloud::ConstPtr;    ///< an input frame
  using Smoother = GraphSmoothing<PointT>;                     ///< the static filter used
  using Ptr = std::shared_ptr<GraphSequenceSmoothing<PointT>>;  ///< shared pointer
  using ConstPtr = std::shared_ptr<const GraphSequenceSmoothing<PointT>>;  ///< shared pointer to const

  /** \brief A sequence smoother with a default GraphTikhonovSmoothing. */
  GraphSequenceSmoothing () : smoother_ (new GraphTikhonovSmoothing<PointT>) {}

  /** \brief The static filter whose smoothing runs on the spatio-temporal graph
   *  (GraphTikhonovSmoothing or GraphTVSmoothing, configured as for a single cloud; its
   *  k is k1). Default: a GraphTikhonovSmoothing with its defaults. Must not be null. */
  inline void
  setSmoother (const typename Smoother::Ptr &smoother) { smoother_ = smoother; }

  /** \brief The static filter used; after a frame is denoised its getUsedGamma(),
   *  getEstimatedNoise() and getSolverReport() describe that frame's solve. */
  inline typename Smoother::Ptr
  getSmoother () const { return smoother_; }

  /** \brief k2: nearest neighbours of each point in each other frame of the window.
   *  Default 3 (the paper suggests k1 > 2 k2; k1 is the smoother's k, 10 by default).
   *  0 = no temporal link: the static filter frame by frame. Valid: >= 0. */
  inline void
  setKTemporal (int k) { k_temporal_ = k; }

  /** \brief The k2 set. */
  inline int
  getKTemporal () const { return k_temporal_; }

  /** \brief Frames t - window ... t + window take part in denoising frame t. Default 1
   *  (the paper's t - 1 and t + 1). 0 = the static filter frame by frame. Valid: >= 0. */
  inline void
  setTemporalWindow (int window) { window_ = window; }

  /** \brief The window set. */
  inline int
  getTemporalWindow () const { return window_; }

  /** \brief Motion compensation: before frame t is smoothed, the points of each other
   *  frame of its window are moved onto frame t's surface (core::surfaceOffsets with its
   *  defaults): first by the rigid motion that best explains the local offsets between
   *  the two frames' surfaces along their normals (30 points of each frame per point),
   *  then each along its normal by the offset that remains, where it is significant
   *  (2 standard errors), smoothed over its neighbours. The temporal links then join
   *  samples of the same surface when it moves between frames (a moving object, a
   *  deforming surface, a registration left imperfect). Motion along the surface is not
   *  seen and needs no compensation. Only frame t's points are returned, so the moved
   *  copies never leave the solve. Default off (the paper's graph on the frames as they
   *  are): on a still scene it cannot tell a sensor's frame-to-frame correlated noise
   *  (depth quantisation, drift) from motion, and keeps what averaging would remove (the
   *  fixed Kinect's frames stay 3.9 mm apart, median, against 1.9 mm without it); turn
   *  it on for surfaces that move between frames by more than about the noise. */
  inline void
  setMotionCompensation (bool on) { motion_compensation_ = on; }

  /** \brief Whether motion compensation is on. */
  inline bool
  getMotionCompensation () const { return motion_compensation_; }

  /** \brief Batch: denoise a whole sequence. On success `output` holds one cloud per
   *  frame (a new cloud, the frames are not modified) and true is returned. On invalid
   *  parameters, a null frame or a failed solve, a PCL_ERROR says why, `output` is
   *  empty and false is returned. An empty sequence gives an empty output. Does not
   *  touch the state of a stream (push). */
  bool
  filter (const std::vector<PointCloudConstPtr> &frames, std::vector<PointCloudPtr> &output);

  /** \brief Batch on non-const frames (as pcl::PointCloud::Ptr vectors usually are). */
  bool
  filter (const std::vector<PointCloudPtr> &frames, std::vector<PointCloudPtr> &output);

  /** \brief Streaming: add the next frame. Once `window` frames have followed a frame,
   *  it is denoised and returned in `denoised` (so with window 1, pushing frame t gives
   *  frame t - 1); until then `denoised` is null. Only the frames still needed are held
   *  (at most 2 window + 1), by shared pointer: do not modify a frame while it is held.
   *  Returns false with a PCL_ERROR (and `denoised` null) on a null frame or invalid
   *  parameters, in which case the frame is not added; or when the due frame's solve
   *  fails, in which case that frame is consumed and reported lost. The result is
   *  that of filter() on all frames pushed, frame by frame. Each push returns at most
   *  one frame: after setTemporalWindow lowers the window mid-stream, the frames already
   *  waiting still come out one per push, so the delay stays at the old window until
   *  flush() (which returns every waiting frame). */
  bool
  push (const PointCloudConstPtr &frame, PointCloudPtr &denoised);

  /** \brief Streaming: the end of the sequence. Denoises the frames still held (the last
   *  `window`, with the frames that exist) into `denoised`, in order, and starts a new
   *  stream. Returns false with a PCL_ERROR if a solve failed (the frames before it are
   *  in `denoised`). */
  bool
  flush (std::vector<PointCloudPtr> &denoised);

  /** \brief Forget the stream's frames (the next push is frame 0 of a new sequence). */
  void
  reset ();

  /** \brief Frames pushed and not yet returned. */
  inline std::size_t
  getNumberOfPendingFrames () const { return pushed_ - next_output_; }

  /** \brief Frames the stream holds now (pending ones and the past ones still in a
   *  window), at most 2 window + 1. */
  inline std::size_t
  getNumberOfHeldFrames () const { return held_.size (); }

protected:
  /** \brief Why the parameters (this class's and the smoother's) are invalid, or empty. */
  std::string
  invalidParameters () const;

  /** \brief Denoise frame `centre` of `window_frames` (consecutive frames, all non-null)
   *  into `output`. False, with a PCL_ERROR, when the solve fails. */
  bool
  denoiseFrame (const std::vector<PointCloudConstPtr> &window_frames, std::size_t centre,
                PointCloudPtr &output);

  /** \brief The frames of the stream's window around frame `t` (global index). */
  std::vector<PointCloudConstPtr>
  heldWindow (std::size_t t, std::size_t &centre) const;

  typename Smoother::Ptr smoother_;  ///< setSmoother
  int k_temporal_ = 3;               ///< setKTemporal
  int window_ = 1;                   ///< setTemporalWindow
  bool motion_compensation_ = false;  ///< setMotionCompensation

  std::deque<PointCloudConstPtr> held_;  ///< the stream's frames first_held_ ... pushed_ - 1
  std::size_t first_held_ = 0;           ///< global index of held_.front ()
  std::size_t pushed_ = 0;               ///< frames pushed since the last reset
  std::size_t next_output_ = 0;          ///< global index of the next frame to return
};

} // namespace pcl_graph_denoise

#ifdef PCL_NO_PRECOMPILE
#include <pcl_graph_denoise/impl/graph_sequence_smoothing.hpp>
#endif

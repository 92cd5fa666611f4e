/*
 * pcl_graph_denoise: graph-signal-processing point cloud denoising for PCL.
 * SPDX-License-Identifier: BSD-3-Clause
 *
 * GraphSequenceSmoothing: the spatio-temporal denoising of a sequence, batch and
 * streaming, its reductions to the static filter, and bad input.
 */
#include <pcl_graph_denoise/graph_sequence_smoothing.h>
#include <pcl_graph_denoise/graph_tikhonov_smoothing.h>
#include <pcl_graph_denoise/graph_tv_smoothing.h>

#include "synthetic.h"
#include "test_clouds.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>

#include <cmath>
#include <limits>

using namespace pcl_graph_denoise;
using pcl_graph_denoise::testing::sameCloud;
using pcl_graph_denoise::testing::withFields;
using Cloud = pcl::PointCloud<pcl::PointXYZ>;
using Frames = std::vector<Cloud::ConstPtr>;
using Outputs = std::vector<Cloud::Ptr>;

namespace {

/** A static unit sphere seen in `count` frames of independent noise, sizes varying. */
Frames
sphereSequence (std::size_t count, std::size_t n, double noise, std::uint64_t seed)
{
  Frames frames;
  for (std::size_t t = 0; t < count; ++t)
    frames.emplace_back (new Cloud (synthetic::noisySphere (n + 37 * t, 1.0, noise, seed + t)));
  return frames;
}

Cloud
staticFilter (const Cloud::ConstPtr &frame, GraphSmoothing<pcl::PointXYZ> &smoother)
{
  smoother.setInputCloud (frame);
  Cloud out;
  smoother.filter (out);
  return out;
}

double
meanSphereError (const Outputs &frames)
{
  double sum = 0.0;
  for (const auto &frame : frames)
    sum += synthetic::meanDistance (*frame, synthetic::distanceToUnitSphere);
  return sum / double (frames.size ());
}

} // namespace

TEST (SequenceSmoothing, OneFrameIsTheStaticFilterBitForBit)
{
  const Frames frames = sphereSequence (1, 1500, 0.02, 11);
  for (bool tv : {false, true})
  {
    GraphSmoothing<pcl::PointXYZ>::Ptr smoother;
    if (tv)
      smoother.reset (new GraphTVSmoothing<pcl::PointXYZ>);
    else
      smoother.reset (new GraphTikhonovSmoothing<pcl::PointXYZ>);
    GraphSequenceSmoothing<pcl::PointXYZ> sequence;
    sequence.setSmoother (smoother);
    Outputs out;
    ASSERT_TRUE (sequence.filter (frames, out));
    ASSERT_EQ (out.size (), 1u);
    GraphTikhonovSmoothing<pcl::PointXYZ> tikhonov;
    GraphTVSmoothing<pcl::PointXYZ> total_variation;
    const Cloud expected = tv ? staticFilter (frames[0], total_variation) : staticFilter (frames[0], tikhonov);
    EXPECT_TRUE (sameCloud (*out[0], expected)) << (tv ? "TV" : "Tikhonov");
    EXPECT_FALSE (sameCloud (*out[0], *frames[0]));
  }
}

TEST (SequenceSmoothing, NoTemporalLinkIsTheStaticFilterFrameByFrame)
{
  const Frames frames = sphereSequence (4, 1200, 0.02, 21);
  GraphTikhonovSmoothing<pcl::PointXYZ> reference;
  for (int variant = 0; variant < 2; ++variant)
  {
    GraphSequenceSmoothing<pcl::PointXYZ> sequence;
    if (variant == 0)
      sequence.setKTemporal (0);
    else
      sequence.setTemporalWindow (0);
    Outputs out;
    ASSERT_TRUE (sequence.filter (frames, out));
    ASSERT_EQ (out.size (), frames.size ());
    for (std::size_t t = 0; t < frames.size (); ++t)
      EXPECT_TRUE (sameCloud (*out[t], staticFilter (frames[t], reference))) << "frame " << t;
  }
}

TEST (SequenceSmoothing, TheSmoothersOwnInputAndIndicesAreLeftAsTheyWere)
{
  // A smoother the caller also uses on its own, with an input cloud and indices of 3
  // points: the sequence smooths whole frames and gives both back (the static path set
  // them to null, dropping the caller's indices and cloud).
  const Frames frames = sphereSequence (3, 800, 0.02, 23);
  auto mine = std::make_shared<pcl::PointCloud<pcl::PointXYZ>> (*frames[0]);
  auto indices = std::make_shared<pcl::Indices> (pcl::Indices{4, 5, 6});
  for (int variant = 0; variant < 2; ++variant)
  {
    auto smoother = std::make_shared<GraphTVSmoothing<pcl::PointXYZ>> ();
    smoother->setInputCloud (mine);
    smoother->setIndices (indices);
    GraphSequenceSmoothing<pcl::PointXYZ> sequence;
    sequence.setSmoother (smoother);
    if (variant == 0)
      sequence.setKTemporal (0);  // the static path; else the temporal one
    Outputs out;
    ASSERT_TRUE (sequence.filter (frames, out));
    EXPECT_EQ (smoother->getInputCloud (), mine) << variant;
    EXPECT_EQ (smoother->getIndices (), indices) << variant;
    // Still the caller's filter: its three points move, the others do not.
    pcl::PointCloud<pcl::PointXYZ> alone;
    smoother->filter (alone);
    std::size_t moved = 0;
    for (std::size_t i = 0; i < mine->size (); ++i)
      moved += alone[i].getVector3fMap () != (*mine)[i].getVector3fMap ();
    EXPECT_LE (moved, 3u) << variant;
    EXPECT_GT (moved, 0u) << variant;
    // Whole frames were smoothed nonetheless.
    std::size_t frame_moved = 0;
    for (std::size_t i = 0; i < frames[1]->size (); ++i)
      frame_moved += (*out[1])[i].getVector3fMap () != (*frames[1])[i].getVector3fMap ();
    EXPECT_GT (frame_moved, frames[1]->size () / 2) << variant;
  }
}

TEST (SequenceSmoothing, NeighbouringFramesLowerTheErrorOfAStaticScene)
{
  // Four frames of one sphere with independent noise: each frame's points gain the
  // samples of its neighbours, at the same derived gamma rule.
  const Frames frames = sphereSequence (4, 2000, 0.02, 31);
  GraphSequenceSmoothing<pcl::PointXYZ> sequence;
  Outputs temporal, per_frame;
  ASSERT_TRUE (sequence.filter (frames, temporal));
  sequence.setKTemporal (0);
  ASSERT_TRUE (sequence.filter (frames, per_frame));
  Outputs noisy;
  for (const auto &frame : frames)
    noisy.emplace_back (new Cloud (*frame));
  const double before = meanSphereError (noisy);
  const double alone = meanSphereError (per_frame);
  const double together = meanSphereError (temporal);
  EXPECT_LT (alone, 0.8 * before);
  EXPECT_LT (together, 0.9 * alone) << "noisy " << before << ", per frame " << alone;
}

TEST (SequenceSmoothing, ExactCopiesInAFrameAreOneVertex)
{
  // Every point of every frame 12 times: its 10 spatial neighbours would all be copies.
  // A frame's copies are one vertex, so each copy moves as the point does in the
  // sequence without copies (motion compensation on, as by default).
  const Frames frames = sphereSequence (3, 1500, 0.02, 41);
  Frames copies;
  for (const auto &frame : frames)
  {
    auto repeated = std::make_shared<Cloud> ();
    for (int c = 0; c < 12; ++c)
      *repeated += *frame;
    copies.push_back (repeated);
  }
  GraphSequenceSmoothing<pcl::PointXYZ> sequence;
  Outputs single, repeated;
  ASSERT_TRUE (sequence.filter (frames, single));
  ASSERT_TRUE (sequence.filter (copies, repeated));
  ASSERT_EQ (repeated.size (), single.size ());
  float largest = 0.0f, moved = 0.0f;
  for (std::size_t f = 0; f < single.size (); ++f)
  {
    ASSERT_EQ (repeated[f]->size (), 12 * single[f]->size ());
    for (std::size_t i = 0; i < repeated[f]->size (); ++i)
    {
      const auto &p = (*repeated[f])[i].getVector3fMap ();
      largest = std::max (largest, (p - (*single[f])[i % single[f]->size ()].getVector3fMap ()).norm ());
      moved = std::max (moved, (p - (*copies[f])[i].getVector3fMap ()).norm ());
    }
  }
  EXPECT_LT (largest, 1e-5f);
  EXPECT_GT (moved, 1e-3f);
}

TEST (SequenceSmoothing, MotionCompensationFollowsAMovingObject)
{
  // A cube turning 2 degrees and sliding 0.03 (3 sigma) per frame: the paper's graph
  // links each point to a neighbouring frame's surface where it no longer is, and does
  // worse than the static filter; moved onto the frame's surface first, the neighbouring
  // frames help as they do for a still scene.
  const double noise = 0.01;
  Frames frames;
  for (int t = 0; t < 4; ++t)
  {
    Eigen::Isometry3d pose = Eigen::Isometry3d::Identity ();
    pose.translate (Eigen::Vector3d (0.03 * t, 0.0, 0.0));
    pose.rotate (Eigen::AngleAxisd (2.0 * M_PI / 180.0 * t, Eigen::Vector3d::UnitZ ()));
    Cloud frame = synthetic::noisyCube (2500, noise, 51 + t);
    for (auto &p : frame)
      p.getVector3fMap () = (pose * p.getVector3fMap ().cast<double> ()).cast<float> ();
    frames.emplace_back (new Cloud (frame));
  }
  const auto error = [&] (const Outputs &out) {
    double sum = 0.0;
    for (int t = 0; t < 4; ++t)
    {
      Eigen::Isometry3d pose = Eigen::Isometry3d::Identity ();
      pose.translate (Eigen::Vector3d (0.03 * t, 0.0, 0.0));
      pose.rotate (Eigen::AngleAxisd (2.0 * M_PI / 180.0 * t, Eigen::Vector3d::UnitZ ()));
      const Eigen::Isometry3d inverse = pose.inverse ();
      sum += synthetic::meanDistance (*out[t], [&] (const Eigen::Vector3d &p) {
        return synthetic::distanceToCube (inverse * p);
      });
    }
    return sum / 4.0;
  };
  GraphSequenceSmoothing<pcl::PointXYZ> sequence;
  EXPECT_FALSE (sequence.getMotionCompensation ());
  Outputs compensated, raw, per_frame;
  ASSERT_TRUE (sequence.filter (frames, raw));
  sequence.setMotionCompensation (true);
  EXPECT_TRUE (sequence.getMotionCompensation ());
  ASSERT_TRUE (sequence.filter (frames, compensated));
  sequence.setKTemporal (0);
  ASSERT_TRUE (sequence.filter (frames, per_frame));
  const double alone = error (per_frame), paper = error (raw), moved = error (compensated);
  EXPECT_GT (paper, alone) << "the paper's graph on moving frames";
  EXPECT_LT (moved, 0.85 * alone) << "per frame " << alone << ", paper's graph " << paper;
}

TEST (SequenceSmoothing, MotionCompensationKeepsAStillSceneOfFramesOfDifferentDensities)
{
  // A still sphere in three frames of 1,000, 4,000 and 1,000 points: with motion
  // compensation the frames do about as well as on the paper's graph (nothing moved);
  // the curvature read as an offset between frames of different densities made the
  // outer frames twice as noisy as their input (0.0159 against 0.0078).
  const double noise = 0.01;
  Frames frames;
  const std::size_t sizes[3] = {1000, 4000, 1000};
  for (std::size_t t = 0; t < 3; ++t)
    frames.emplace_back (new Cloud (synthetic::noisySphere (sizes[t], 1.0, noise, 7 + t)));
  GraphSequenceSmoothing<pcl::PointXYZ> sequence;
  Outputs paper, compensated;
  ASSERT_TRUE (sequence.filter (frames, paper));
  sequence.setMotionCompensation (true);
  ASSERT_TRUE (sequence.filter (frames, compensated));
  for (std::size_t t = 0; t < 3; ++t)
  {
    const double still = synthetic::meanDistance (*paper[t], synthetic::distanceToUnitSphere);
    const double moved = synthetic::meanDistance (*compensated[t], synthetic::distanceToUnitSphere);
    EXPECT_LT (moved, 1.35 * still) << "frame " << t;
    EXPECT_LT (moved, 0.2 * noise) << "frame " << t;
  }
}

TEST (SequenceSmoothing, StreamingGivesTheBatchResultWithBoundedMemory)
{
  Frames frames = sphereSequence (6, 900, 0.02, 41);
  // An empty frame and a frame with non-finite points in the middle.
  frames[2] = Cloud::ConstPtr (new Cloud);
  {
    Cloud::Ptr holes (new Cloud (*frames[3]));
    for (std::size_t i = 0; i < holes->size (); i += 7)
      (*holes)[i].y = std::numeric_limits<float>::quiet_NaN ();
    holes->is_dense = false;
    frames[3] = holes;
  }
  for (int window : {1, 2})
  {
    GraphSequenceSmoothing<pcl::PointXYZ> sequence;
    sequence.setTemporalWindow (window);
    Outputs batch;
    ASSERT_TRUE (sequence.filter (frames, batch));
    ASSERT_EQ (batch.size (), frames.size ());
    Outputs streamed;
    for (std::size_t t = 0; t < frames.size (); ++t)
    {
      Cloud::Ptr ready;
      ASSERT_TRUE (sequence.push (frames[t], ready));
      if (t < std::size_t (window))
        EXPECT_FALSE (ready) << "frame " << t << " came out before its window was complete";
      else
        ASSERT_TRUE (ready) << "frame " << t - window << " did not come out at frame " << t;
      if (ready)
        streamed.push_back (ready);
      EXPECT_LE (sequence.getNumberOfHeldFrames (), std::size_t (2 * window + 1));
      EXPECT_EQ (sequence.getNumberOfPendingFrames (), std::min<std::size_t> (t + 1, window));
    }
    Outputs rest;
    ASSERT_TRUE (sequence.flush (rest));
    EXPECT_EQ (rest.size (), std::size_t (window));
    EXPECT_EQ (sequence.getNumberOfHeldFrames (), 0u);
    streamed.insert (streamed.end (), rest.begin (), rest.end ());
    ASSERT_EQ (streamed.size (), batch.size ());
    for (std::size_t t = 0; t < batch.size (); ++t)
      EXPECT_TRUE (sameCloud (*streamed[t], *batch[t])) << "window " << window << ", frame " << t;
    EXPECT_EQ (batch[2]->size (), 0u);
    // Non-finite points pass through; the others moved.
    for (std::size_t i = 0; i < frames[3]->size (); ++i)
      if (i % 7 == 0)
        EXPECT_TRUE (std::isnan ((*batch[3])[i].y));
  }
}

TEST (SequenceSmoothing, AWindowLoweredMidStreamStillReturnsEveryFrame)
{
  // Window 2, then 0 after three frames: each push returns one frame, so the two waiting
  // frames keep the delay at 2 (as documented) and flush() returns them; none is lost or
  // returned twice.
  const Frames frames = sphereSequence (6, 600, 0.02, 43);
  GraphSequenceSmoothing<pcl::PointXYZ> sequence;
  sequence.setTemporalWindow (2);
  std::size_t returned = 0;
  for (std::size_t t = 0; t < frames.size (); ++t)
  {
    if (t == 3)
      sequence.setTemporalWindow (0);
    Cloud::Ptr ready;
    ASSERT_TRUE (sequence.push (frames[t], ready));
    EXPECT_EQ (bool (ready), t >= 2) << "frame " << t;
    if (ready)
    {
      EXPECT_EQ (ready->size (), frames[returned]->size ());
      ++returned;
    }
    EXPECT_EQ (sequence.getNumberOfPendingFrames (), std::min<std::size_t> (t + 1, 2)) << t;
  }
  Outputs rest;
  ASSERT_TRUE (sequence.flush (rest));
  EXPECT_EQ (returned + rest.size (), frames.size ());
  EXPECT_EQ (rest.size (), 2u);
}

TEST (SequenceSmoothing, AFrameDependsOnlyOnTheFramesOfItsWindow)
{
  Frames frames = sphereSequence (5, 800, 0.02, 51);
  GraphSequenceSmoothing<pcl::PointXYZ> sequence;
  Outputs first, second;
  ASSERT_TRUE (sequence.filter (frames, first));
  frames[4] = Cloud::ConstPtr (new Cloud (synthetic::noisySphere (800, 1.0, 0.05, 99)));
  ASSERT_TRUE (sequence.filter (frames, second));
  for (std::size_t t = 0; t < 3; ++t)
    EXPECT_TRUE (sameCloud (*first[t], *second[t])) << "frame " << t;
  EXPECT_FALSE (sameCloud (*first[3], *second[3]));
}

TEST (SequenceSmoothing, TheNumberOfThreadsDoesNotChangeTheResult)
{
  const Frames frames = sphereSequence (3, 1500, 0.02, 61);
  Outputs one, two;
  GraphSequenceSmoothing<pcl::PointXYZ> sequence;
  sequence.getSmoother ()->setNumberOfThreads (1);
  ASSERT_TRUE (sequence.filter (frames, one));
  sequence.getSmoother ()->setNumberOfThreads (2);
  ASSERT_TRUE (sequence.filter (frames, two));
  for (std::size_t t = 0; t < frames.size (); ++t)
    EXPECT_TRUE (sameCloud (*one[t], *two[t])) << "frame " << t;
}

TEST (SequenceSmoothing, OnlyXyzChangeAndEveryFieldOrganisationAndHeaderSurvive)
{
  using PointT = pcl::PointXYZRGBNormal;
  std::vector<pcl::PointCloud<PointT>::Ptr> frames;
  for (std::size_t t = 0; t < 3; ++t)
  {
    auto frame = withFields<PointT> (synthetic::noisySphere (1200, 1.0, 0.02, 70 + t));
    frame->width = 40;
    frame->height = 30;
    (*frame)[5].z = std::numeric_limits<float>::infinity ();
    frame->is_dense = false;
    frames.push_back (frame);
  }
  std::vector<pcl::PointCloud<PointT>> before;
  for (const auto &frame : frames)
    before.push_back (*frame);
  GraphSequenceSmoothing<PointT> sequence;
  sequence.setSmoother (GraphSmoothing<PointT>::Ptr (new GraphTVSmoothing<PointT>));
  std::vector<pcl::PointCloud<PointT>::Ptr> out;
  ASSERT_TRUE (sequence.filter (frames, out));
  ASSERT_EQ (out.size (), 3u);
  for (std::size_t t = 0; t < 3; ++t)
  {
    EXPECT_TRUE (sameCloud (*frames[t], before[t])) << "the input frame was modified";
    const auto &o = *out[t];
    ASSERT_EQ (o.size (), before[t].size ());
    EXPECT_EQ (o.width, 40u);
    EXPECT_EQ (o.height, 30u);
    EXPECT_FALSE (o.is_dense);
    EXPECT_EQ (o.header.frame_id, before[t].header.frame_id);
    EXPECT_EQ (o.header.stamp, before[t].header.stamp);
    std::size_t moved = 0;
    for (std::size_t i = 0; i < o.size (); ++i)
    {
      PointT a = o[i], b = before[t][i];
      moved += (a.x != b.x || a.y != b.y || a.z != b.z);
      a.x = b.x, a.y = b.y, a.z = b.z;
      EXPECT_TRUE (pcl_graph_denoise::testing::samePoint (a, b)) << "a field other than x, y, z changed";
    }
    EXPECT_TRUE (std::isinf (o[5].z));
    EXPECT_GT (moved, o.size () / 2);
  }
}

TEST (SequenceSmoothing, InvalidParametersAndNullFramesAreRefusedWithoutOutput)
{
  const Frames frames = sphereSequence (3, 500, 0.02, 81);
  Outputs out;
  out.emplace_back (new Cloud);
  GraphSequenceSmoothing<pcl::PointXYZ> sequence;

  sequence.setKTemporal (-1);
  EXPECT_FALSE (sequence.filter (frames, out));
  EXPECT_TRUE (out.empty ());
  sequence.setKTemporal (3);
  sequence.setTemporalWindow (-2);
  EXPECT_FALSE (sequence.filter (frames, out));
  sequence.setTemporalWindow (1);
  sequence.getSmoother ()->setKSearch (0);
  EXPECT_FALSE (sequence.filter (frames, out));
  sequence.getSmoother ()->setKSearch (10);
  sequence.getSmoother ()->setGamma (std::numeric_limits<double>::quiet_NaN ());
  EXPECT_FALSE (sequence.filter (frames, out));
  sequence.getSmoother ()->setAutomaticGamma ();
  sequence.setSmoother (nullptr);
  EXPECT_FALSE (sequence.filter (frames, out));
  sequence.setSmoother (GraphSmoothing<pcl::PointXYZ>::Ptr (new GraphTikhonovSmoothing<pcl::PointXYZ>));

  Frames with_null = frames;
  with_null[1] = nullptr;
  EXPECT_FALSE (sequence.filter (with_null, out));
  EXPECT_TRUE (out.empty ());

  // Streaming refuses a null frame without adding it; the stream goes on.
  Cloud::Ptr ready;
  ASSERT_TRUE (sequence.push (frames[0], ready));
  EXPECT_FALSE (sequence.push (nullptr, ready));
  EXPECT_FALSE (ready);
  EXPECT_EQ (sequence.getNumberOfPendingFrames (), 1u);
  ASSERT_TRUE (sequence.push (frames[1], ready));
  ASSERT_TRUE (ready);
  sequence.reset ();
  EXPECT_EQ (sequence.getNumberOfPendingFrames (), 0u);
  EXPECT_EQ (sequence.getNumberOfHeldFrames (), 0u);

  // A memory limit too small for a window fails the frame with an error, no crash.
  sequence.getSmoother ()->setMemoryLimit (1000);
  EXPECT_FALSE (sequence.filter (frames, out));
  EXPECT_TRUE (out.empty ());
}

TEST (SequenceSmoothing, AFailedSolveInAStreamLosesOnlyThatFrameAndSaysSo)
{
  const Frames frames = sphereSequence (4, 600, 0.02, 85);
  GraphSequenceSmoothing<pcl::PointXYZ> sequence;
  Outputs batch;
  ASSERT_TRUE (sequence.filter (frames, batch));
  Cloud::Ptr ready;
  ASSERT_TRUE (sequence.push (frames[0], ready));
  // Frame 0's solve is refused (memory limit): push reports it, frame 0 is gone.
  sequence.getSmoother ()->setMemoryLimit (1000);
  EXPECT_FALSE (sequence.push (frames[1], ready));
  EXPECT_FALSE (ready);
  EXPECT_EQ (sequence.getNumberOfPendingFrames (), 1u);
  // The stream goes on: frame 1 comes out as in the batch.
  sequence.getSmoother ()->setMemoryLimit (0);
  ASSERT_TRUE (sequence.push (frames[2], ready));
  ASSERT_TRUE (ready);
  EXPECT_TRUE (sameCloud (*ready, *batch[1]));
  ASSERT_TRUE (sequence.push (frames[3], ready));
  EXPECT_TRUE (sameCloud (*ready, *batch[2]));
  // A failing flush returns false and what it produced before the failure (none here).
  sequence.getSmoother ()->setMemoryLimit (1000);
  Outputs rest;
  EXPECT_FALSE (sequence.flush (rest));
  EXPECT_TRUE (rest.empty ());
  EXPECT_EQ (sequence.getNumberOfHeldFrames (), 0u);
}

TEST (SequenceSmoothing, DegenerateSequencesAreDefined)
{
  GraphSequenceSmoothing<pcl::PointXYZ> sequence;
  Outputs out;
  EXPECT_TRUE (sequence.filter (Frames{}, out));
  EXPECT_TRUE (out.empty ());

  // Only empty and all-NaN frames: returned unchanged.
  Cloud::Ptr nan_frame (new Cloud);
  nan_frame->resize (20);
  for (auto &p : *nan_frame)
    p.x = p.y = p.z = std::numeric_limits<float>::quiet_NaN ();
  nan_frame->is_dense = false;
  const Frames degenerate = {Cloud::ConstPtr (new Cloud), nan_frame, Cloud::ConstPtr (new Cloud)};
  ASSERT_TRUE (sequence.filter (degenerate, out));
  ASSERT_EQ (out.size (), 3u);
  EXPECT_TRUE (out[0]->empty ());
  EXPECT_TRUE (sameCloud (*out[1], *nan_frame));

  // Tiny frames (fewer points than k) and duplicate points beside a normal frame.
  Cloud::Ptr tiny (new Cloud);
  tiny->push_back (pcl::PointXYZ (0.f, 0.f, 1.f));
  tiny->push_back (pcl::PointXYZ (0.f, 0.f, 1.f));
  tiny->push_back (pcl::PointXYZ (0.01f, 0.f, 1.f));
  const Frames mixed = {tiny, sphereSequence (1, 600, 0.02, 91)[0], tiny};
  ASSERT_TRUE (sequence.filter (mixed, out));
  ASSERT_EQ (out.size (), 3u);
  for (std::size_t t = 0; t < 3; ++t)
    for (const auto &p : *out[t])
      EXPECT_TRUE (std::isfinite (p.x) && std::isfinite (p.y) && std::isfinite (p.z));

  // gamma = 0 is the identity.
  sequence.getSmoother ()->setGamma (0.0);
  const Frames frames = sphereSequence (2, 500, 0.02, 95);
  ASSERT_TRUE (sequence.filter (frames, out));
  EXPECT_TRUE (sameCloud (*out[0], *frames[0]));
  EXPECT_TRUE (sameCloud (*out[1], *frames[1]));
}

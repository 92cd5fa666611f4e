/*
 * pcl_graph_denoise: graph-signal-processing point cloud denoising for PCL.
 * SPDX-License-Identifier: BSD-3-Clause
 *
 * Time-varying clouds (issue 5): synthetic sequences with known surfaces, 20 frames of
 * 5,000 points each with independent Gaussian noise (0.5%, 1%, 2% of the unit size):
 *  - a moving cube [-1,1]^3, turning 1.5 degrees per frame about z and sliding 0.01 along x;
 *  - a rotating unit sphere, 2 degrees per frame about (1, 1, 0);
 *  - a waving plane z = 0.1 sin(2 pi (x - t / 20)) over [-1,1]^2, one period in 20 frames.
 * Mean distance to the true surface of frame t, averaged over the frames, for the static
 * filter frame by frame and for GraphSequenceSmoothing (k2 = 3, window 1) with motion
 * compensation: both with their data-derived gamma, both at the same gamma (the static
 * filter's derived gamma on frame 0), and each at its best gamma of a sweep (1/4x to 4x
 * that gamma); and without motion compensation (its default) at the same gamma. Tikhonov
 * and TV. Then the time per frame of 10 frames of 100,000 points (a noisy sphere), static
 * against temporal with and without motion compensation. Then the real sequence of a fixed
 * Kinect (../shared/data/sequences/pcl_grabber_kinect): temporal stability (distance of
 * frame t's points to frame t + 1's surface) raw, frame by frame, temporal, and temporal
 * with motion compensation, with frame 1 saved for the pictures
 * (kinect_frame1_*.pcd, the distance in mm as intensity). Writes sequences.md. Quick mode: 8 frames of 5,000 points at 1%, the
 * equal-gamma comparison only, and asserts the report's claim that the temporal filter
 * beats the static one at equal gamma on every sequence.
 */
#include "evaluate.h"

#include <pcl_graph_denoise/graph_sequence_smoothing.h>
#include <pcl_graph_denoise/graph_tikhonov_smoothing.h>
#include <pcl_graph_denoise/graph_tv_smoothing.h>

#include "synthetic.h"
#include "timing.h"

#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>

#include <pcl/common/point_tests.h>
#include <pcl/io/pcd_io.h>
#include <pcl/kdtree/kdtree_flann.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <limits>
#include <numeric>
#include <cstdio>
#include <fstream>
#include <functional>
#include <random>
#include <stdexcept>
#include <string>
#include <vector>

namespace pcl_graph_denoise {
namespace evaluation {

namespace {

using Frames = std::vector<Cloud::ConstPtr>;
using Outputs = std::vector<Cloud::Ptr>;

/** A sequence: frame t sampled with noise, and the distance to frame t's true surface. */
struct Sequence
{
  const char *name;
  std::function<Cloud (double time, std::size_t n, double noise, std::uint64_t seed)> sample;
  std::function<double (double time, const Eigen::Vector3d &p)> distance;
};

Cloud
transformed (const Cloud &cloud, const Eigen::Isometry3d &pose)
{
  Cloud out = cloud;
  for (auto &p : out)
    p.getVector3fMap () = (pose * p.getVector3fMap ().cast<double> ()).cast<float> ();
  return out;
}

/** The motion per frame is `speed` times the nominal one (time runs speed x faster). */
Eigen::Isometry3d
cubePose (double time)
{
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity ();
  pose.translate (Eigen::Vector3d (0.01 * time, 0.0, 0.0));
  pose.rotate (Eigen::AngleAxisd (1.5 * M_PI / 180.0 * time, Eigen::Vector3d::UnitZ ()));
  return pose;
}

Eigen::Isometry3d
spherePose (double time)
{
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity ();
  pose.rotate (Eigen::AngleAxisd (2.0 * M_PI / 180.0 * time, Eigen::Vector3d (1, 1, 0).normalized ()));
  return pose;
}

constexpr double kWaveAmplitude = 0.1;
constexpr double kWaveFrames = 20.0;

double
waveHeight (double time, double x)
{
  return kWaveAmplitude * std::sin (2.0 * M_PI * (x - time / kWaveFrames));
}

/** Exact distance to the waving plane (infinite in y): the closest point of the curve
 *  z = h(x) in the x-z plane, by a fine scan then golden-section refinement. */
double
distanceToWave (double t, const Eigen::Vector3d &p)
{
  const auto d2 = [&] (double x) {
    const double dz = p.z () - waveHeight (t, x);
    return (x - p.x ()) * (x - p.x ()) + dz * dz;
  };
  const double reach = std::abs (p.z ()) + kWaveAmplitude;
  double best = p.x (), best_d2 = d2 (p.x ());
  const int steps = 64;
  for (int i = -steps; i <= steps; ++i)
  {
    const double x = p.x () + reach * double (i) / steps;
    if (d2 (x) < best_d2)
      best = x, best_d2 = d2 (x);
  }
  double a = best - reach / steps, b = best + reach / steps;
  const double g = 0.5 * (std::sqrt (5.0) - 1.0);
  for (int i = 0; i < 40; ++i)
  {
    const double c = b - g * (b - a), d = a + g * (b - a);
    if (d2 (c) < d2 (d))
      b = d;
    else
      a = c;
  }
  return std::sqrt (std::min (best_d2, d2 (0.5 * (a + b))));
}

std::vector<Sequence>
sequences ()
{
  return {
      {"moving cube",
       [] (double t, std::size_t n, double noise, std::uint64_t seed) {
         return transformed (synthetic::noisyCube (n, noise, seed), cubePose (t));
       },
       [] (double t, const Eigen::Vector3d &p) {
         return synthetic::distanceToCube (cubePose (t).inverse () * p);
       }},
      {"rotating sphere",
       [] (double t, std::size_t n, double noise, std::uint64_t seed) {
         return transformed (synthetic::noisySphere (n, 1.0, noise, seed), spherePose (t));
       },
       [] (double, const Eigen::Vector3d &p) { return synthetic::distanceToUnitSphere (p); }},
      {"waving plane",
       [] (double t, std::size_t n, double noise, std::uint64_t seed) {
         std::mt19937_64 rng (seed);
         std::uniform_real_distribution<double> u (-1.0, 1.0);
         std::normal_distribution<double> g (0.0, noise);
         Cloud cloud;
         for (std::size_t i = 0; i < n; ++i)
         {
           const double x = u (rng), y = u (rng);
           cloud.push_back (pcl::PointXYZ (float (x + g (rng)), float (y + g (rng)),
                                           float (waveHeight (t, x) + g (rng))));
         }
         return cloud;
       },
       distanceToWave},
  };
}

double
sequenceError (const Sequence &sequence, double speed, const Outputs &frames)
{
  double sum = 0.0;
  for (std::size_t t = 0; t < frames.size (); ++t)
  {
    double frame_sum = 0.0;
    for (const auto &p : *frames[t])
      frame_sum += sequence.distance (speed * double (t), p.getVector3fMap ().cast<double> ());
    sum += frame_sum / double (frames[t]->size ());
  }
  return sum / double (frames.size ());
}

/** Runs a smoother on the sequence, frame by frame (k2 = 0, exactly the static filter)
 *  or spatio-temporally (with or without motion compensation); gamma < 0 = the
 *  data-derived one. */
Outputs
run (const GraphSmoothing<pcl::PointXYZ>::Ptr &smoother, const Frames &frames, bool temporal,
     bool motion_compensation, double gamma, double *seconds = nullptr)
{
  if (gamma < 0.0)
    smoother->setAutomaticGamma ();
  else
    smoother->setGamma (gamma);
  GraphSequenceSmoothing<pcl::PointXYZ> sequence;
  sequence.setSmoother (smoother);
  sequence.setKTemporal (temporal ? 3 : 0);
  sequence.setMotionCompensation (motion_compensation);
  Outputs out;
  bool ok = false;
  const double took = pcl_graph_denoise::seconds ([&] { ok = sequence.filter (frames, out); });
  if (!ok)
    throw std::runtime_error ("the sequence smoothing failed");
  if (seconds)
    *seconds = took;
  return out;
}

GraphSmoothing<pcl::PointXYZ>::Ptr
makeSmoother (bool tv)
{
  if (tv)
    return GraphSmoothing<pcl::PointXYZ>::Ptr (new GraphTVSmoothing<pcl::PointXYZ>);
  return GraphSmoothing<pcl::PointXYZ>::Ptr (new GraphTikhonovSmoothing<pcl::PointXYZ>);
}

/** Point-to-plane distance of each finite point of `from` to the surface of `to` (the
 *  plane fitted to its 10 nearest points there); NaN for non-finite points. */
std::vector<double>
distancesToSurface (const Cloud &from, const Cloud &to)
{
  Cloud::Ptr finite (new Cloud);
  for (const auto &p : to)
    if (pcl::isFinite (p))
      finite->push_back (p);
  pcl::KdTreeFLANN<pcl::PointXYZ> tree;
  tree.setInputCloud (finite);
  std::vector<double> distance (from.size (), std::numeric_limits<double>::quiet_NaN ());
  pcl::Indices index;
  std::vector<float> d2;
  for (std::size_t i = 0; i < from.size (); ++i)
  {
    if (!pcl::isFinite (from[i]) || tree.nearestKSearch (from[i], 10, index, d2) < 3)
      continue;
    Eigen::Vector3d centre = Eigen::Vector3d::Zero ();
    for (const auto j : index)
      centre += (*finite)[j].getVector3fMap ().cast<double> ();
    centre /= double (index.size ());
    Eigen::Matrix3d covariance = Eigen::Matrix3d::Zero ();
    for (const auto j : index)
    {
      const Eigen::Vector3d d = (*finite)[j].getVector3fMap ().cast<double> () - centre;
      covariance += d * d.transpose ();
    }
    const Eigen::Vector3d normal = Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> (covariance).eigenvectors ().col (0);
    distance[i] = std::abs (normal.dot (from[i].getVector3fMap ().cast<double> () - centre));
  }
  return distance;
}

/** Mean and median of the finite values. */
std::pair<double, double>
meanAndMedian (std::vector<double> values)
{
  values.erase (std::remove_if (values.begin (), values.end (), [] (double v) { return !std::isfinite (v); }),
                values.end ());
  if (values.empty ())
    return {0.0, 0.0};
  const double mean = std::accumulate (values.begin (), values.end (), 0.0) / double (values.size ());
  std::nth_element (values.begin (), values.begin () + values.size () / 2, values.end ());
  return {mean, values[values.size () / 2]};
}

/** Temporal stability of a sequence: the distance of frame t's points to frame t + 1's
 *  surface and back, over all consecutive pairs (mean and median, in the cloud's units). */
std::pair<double, double>
stability (const std::vector<Cloud::Ptr> &frames)
{
  std::vector<double> all;
  for (std::size_t t = 0; t + 1 < frames.size (); ++t)
    for (const auto &[a, b] : {std::make_pair (t, t + 1), std::make_pair (t + 1, t)})
    {
      const auto d = distancesToSurface (*frames[a], *frames[b]);
      all.insert (all.end (), d.begin (), d.end ());
    }
  return meanAndMedian (all);
}

/** A frame with, as intensity, the distance of each point to the next frame's surface
 *  in mm (for the pictures). */
void
saveStability (const std::string &path, const Cloud &frame, const Cloud &next)
{
  const auto d = distancesToSurface (frame, next);
  pcl::PointCloud<pcl::PointXYZI> out;
  for (std::size_t i = 0; i < frame.size (); ++i)
  {
    pcl::PointXYZI p;
    p.getVector3fMap () = frame[i].getVector3fMap ();
    p.intensity = static_cast<float> (1000.0 * d[i]);
    out.push_back (p);
  }
  out.width = frame.width;
  out.height = frame.height;
  out.is_dense = false;
  pcl::io::savePCDFileBinary (path, out);
}

/** The fixed Kinect's three frames of a static scene (../shared/data/sequences/
 *  pcl_grabber_kinect): temporal stability before and after. Returns false when the
 *  data is missing. */
bool
kinectStability (const Options &options, std::ostream &md, double &raw_median, double &temporal_median,
                 double &per_frame_median, double &compensated_median)
{
  const std::string folder = options.data + "/sequences/pcl_grabber_kinect/";
  const char *names[] = {"frame_20121214T142255.814212.pcd", "frame_20121214T142256.068683.pcd",
                         "frame_20121214T142256.332395.pcd"};
  std::vector<Cloud::Ptr> raw;
  for (const char *name : names)
  {
    raw.emplace_back (new Cloud);
    if (pcl::io::loadPCDFile (folder + name, *raw.back ()) != 0)
      return false;
  }
  const Frames frames (raw.begin (), raw.end ());
  const auto before = stability (raw);
  raw_median = before.second;
  md << "\nReal sequence: the fixed Kinect's three frames of a static scene "
        "(`sequences/pcl_grabber_kinect`, 640 x 480, about 271,000 finite points each, ~0.25 s "
        "apart). No ground truth: temporal stability, the distance of frame t's points to the "
        "plane of their 10 nearest points in frame t + 1 and back (mm), and the time for the three "
        "frames. Defaults (k2 = 3, window 1, no motion compensation), and with motion "
        "compensation.\n\n| | mean (mm) | median (mm) | seconds |\n|---|---|---|---|\n";
  char line[160];
  std::snprintf (line, sizeof (line), "| raw frames | %.3f | %.3f | |\n", 1e3 * before.first, 1e3 * before.second);
  md << line;
  std::printf ("kinect raw: mean %.3f mm, median %.3f mm\n", 1e3 * before.first, 1e3 * before.second);
  saveStability (options.out + "/kinect_frame1_raw.pcd", *raw[1], *raw[2]);
  // 0: frame by frame, 1: temporal (the default), 2: temporal with motion compensation.
  const char *const labels[] = {"frame by frame", "temporal", "temporal, motion compensation"};
  for (bool tv : {false, true})
    for (int variant = 0; variant < 3; ++variant)
    {
      double seconds = 0.0;
      const Outputs out = run (makeSmoother (tv), frames, variant > 0, variant == 2, -1.0, &seconds);
      const auto after = stability (out);
      std::snprintf (line, sizeof (line), "| %s, %s | %.3f | %.3f | %.1f |\n", tv ? "TV" : "Tikhonov",
                     labels[variant], 1e3 * after.first, 1e3 * after.second, seconds);
      md << line;
      std::printf ("kinect %s %s: mean %.3f mm, median %.3f mm, %.1f s\n", tv ? "TV" : "Tikhonov",
                   labels[variant], 1e3 * after.first, 1e3 * after.second, seconds);
      if (!tv)
        (variant == 0 ? per_frame_median : variant == 1 ? temporal_median : compensated_median) = after.second;
      if (!tv && variant < 2)
        saveStability (options.out + "/kinect_frame1_" + (variant ? "temporal" : "per_frame") + ".pcd",
                       *out[1], *out[2]);
    }
  return true;
}

} // namespace

int
sequences (const Options &options)
{
  const std::size_t frame_count = options.quick ? 8 : 20;
  // The quick mode keeps the full run's density (fewer frames, one noise level): at 2,000
  // points a frame the cube's edges fill the two-ring fits, the noise estimate reads twice
  // the noise, and with the detail term the two filters tie there (TV).
  const std::size_t n = 5000;
  const std::vector<double> noises = options.quick ? std::vector<double>{0.01}
                                                   : std::vector<double>{0.005, 0.01, 0.02};
  const std::vector<double> factors = {0.25, 0.5, 1.0, 2.0, 4.0};
  std::ofstream md (options.out + "/sequences.md");
  md << "Synthetic sequences: " << frame_count << " frames of " << n
     << " points, independent Gaussian noise per frame; mean distance to frame t's true surface, "
        "averaged over the frames (x 10^3). Per frame = the static filter on each frame alone; "
        "temporal = GraphSequenceSmoothing (k1 = 10, k2 = 3, window 1) with motion compensation "
        "on; uncompensated = the same with its default, no motion compensation (the paper's graph "
        "on the frames as they are). Same γ: all at the "
        "static filter's derived γ on frame 0. Best: each at the best of "
     << factors.front () << "x to " << factors.back ()
     << "x that γ. Gain = 1 - temporal / per frame.\n\n"
        "| sequence | speed | σ | filter | noisy | per frame (defaults) | temporal (defaults) | per frame "
        "(same γ) | temporal (same γ) | gain at same γ | uncompensated (same γ) | its gain | per frame (best γ) | temporal (best γ) |\n"
        "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|\n";
  // Smallest gain at the same gamma, per speed (0.25, 1).
  double smallest_gain[2] = {1.0, 1.0};
  double smallest_paper_gain[2] = {1.0, 1.0};  // without motion compensation
  for (const double speed : {0.25, 1.0})
  for (const Sequence &sequence : sequences ())
    for (double noise : noises)
    {
      Frames frames;
      for (std::size_t t = 0; t < frame_count; ++t)
        frames.emplace_back (new Cloud (sequence.sample (speed * double (t), n, noise, 9000 + 31 * t)));
      Outputs noisy;
      for (const auto &f : frames)
        noisy.emplace_back (new Cloud (*f));
      const double before = sequenceError (sequence, speed, noisy);
      for (bool tv : {false, true})
      {
        const auto smoother = makeSmoother (tv);
        smoother->setInputCloud (frames[0]);
        Cloud first;
        smoother->filter (first);
        const double gamma = smoother->getUsedGamma ();
        const double alone_same = sequenceError (sequence, speed, run (smoother, frames, false, false, gamma));
        const double together_same = sequenceError (sequence, speed, run (smoother, frames, true, true, gamma));
        const double gain = 1.0 - together_same / alone_same;
        double &smallest = smallest_gain[speed < 1.0 ? 0 : 1];
        smallest = std::min (smallest, gain);
        std::string cells;
        char cell[64], paper_cells[64] = " |";
        if (!options.quick)
        {
          const double paper = sequenceError (sequence, speed, run (smoother, frames, true, false, gamma));
          smallest_paper_gain[speed < 1.0 ? 0 : 1] = std::min (smallest_paper_gain[speed < 1.0 ? 0 : 1], 1.0 - paper / alone_same);
          std::snprintf (paper_cells, sizeof (paper_cells), "%.3f | %ld%%", 1e3 * paper,
                         std::lround (100.0 * (1.0 - paper / alone_same)));
          const double alone = sequenceError (sequence, speed, run (smoother, frames, false, false, -1.0));
          const double together = sequenceError (sequence, speed, run (smoother, frames, true, true, -1.0));
          double best_alone = alone_same, best_together = together_same;
          for (double f : factors)
            if (f != 1.0)
            {
              best_alone = std::min (best_alone, sequenceError (sequence, speed, run (smoother, frames, false, false, f * gamma)));
              best_together = std::min (best_together, sequenceError (sequence, speed, run (smoother, frames, true, true, f * gamma)));
            }
          std::snprintf (cell, sizeof (cell), "%.3f | %.3f", 1e3 * alone, 1e3 * together);
          cells = cell;
          std::snprintf (cell, sizeof (cell), "%.3f | %.3f", 1e3 * best_alone, 1e3 * best_together);
        }
        char same[160];
        std::snprintf (same, sizeof (same), "%.3f | %s | %.3f | %.3f | %ld%% | %s | %s", 1e3 * before,
                       options.quick ? " |" : cells.c_str (), 1e3 * alone_same, 1e3 * together_same,
                       std::lround (100.0 * gain), paper_cells, options.quick ? " |" : cell);
        md << "| " << sequence.name << " | " << speed << " | " << noise << " | " << (tv ? "TV" : "Tikhonov")
           << " | " << same << " |\n";
        std::printf ("%s speed %g sigma %g %s: noisy %.4f, same gamma: per frame %.4f, temporal %.4f (gain %.0f%%)\n",
                     sequence.name, speed, noise, tv ? "TV" : "Tikhonov", before, alone_same, together_same,
                     100.0 * gain);
      }
    }

  if (!options.quick)
  {
    // Speed: 10 frames of 100,000 points, time per frame.
    Frames frames;
    for (std::size_t t = 0; t < 10; ++t)
      frames.emplace_back (new Cloud (synthetic::noisySphere (100000, 1.0, 0.01, 9500 + t)));
    md << "\nSpeed: 10 frames of 100,000 points (noisy sphere, σ = 1%), seconds per frame, "
          "defaults, this machine (2 cores); temporal: the default, and with motion compensation."
          "\n\n| filter | per frame | temporal | ratio | temporal, motion compensation | ratio |\n"
          "|---|---|---|---|---|---|\n";
    for (bool tv : {false, true})
    {
      double alone = 0.0, together = 0.0, moved = 0.0;
      run (makeSmoother (tv), frames, false, false, -1.0, &alone);
      run (makeSmoother (tv), frames, true, false, -1.0, &together);
      run (makeSmoother (tv), frames, true, true, -1.0, &moved);
      char row[160];
      std::snprintf (row, sizeof (row), "| %s | %.3f | %.3f | %.2fx | %.3f | %.2fx |\n",
                     tv ? "TV" : "Tikhonov", alone / 10.0, together / 10.0, together / alone,
                     moved / 10.0, moved / alone);
      md << row;
      std::printf ("speed %s: %.3f s per frame alone, %.3f s temporal (%.2fx), %.3f s with motion "
                   "compensation (%.2fx)\n", tv ? "TV" : "Tikhonov", alone / 10.0, together / 10.0,
                   together / alone, moved / 10.0, moved / alone);
    }
  }

  double raw_median = 0.0, temporal_median = 0.0, per_frame_median = 0.0, compensated_median = 0.0;
  bool kinect = false;
  if (!options.quick)
  {
    kinect = kinectStability (options, md, raw_median, temporal_median, per_frame_median,
                              compensated_median);
    if (!kinect)
    {
      // The shared data sits beside the clone: absent in a user's clone, required under CI.
      const char *ci = std::getenv ("CI");
      const bool under_ci = ci != nullptr && std::string (ci) == "true";
      std::fprintf (stderr, "%s: the Kinect sequence was not found in %s\n",
                    under_ci ? "error" : "skipped", options.data.c_str ());
      if (under_ci)
        return 1;
    }
  }

  md << "\n";
  const auto percent = [] (double gain) { return std::to_string (std::lround (100.0 * gain)) + "%"; };
  std::vector<Finding> findings = {
      {"at speed 0.25 (each surface moves about 1σ or less per frame at σ = 1%) the temporal filter "
       "has a lower error than the static one frame by frame at the same γ on every sequence, noise "
       "level and filter (smallest gain " + percent (smallest_gain[0]) + ")",
       smallest_gain[0] > 0.0, true},
      {"at speed 0.25 the gain at the same γ is at least 25% everywhere (the issue's target)",
       smallest_gain[0] >= 0.25, false},
      {"at speed 1 (motion of 3-4σ per frame at σ = 1%) the temporal filter is still better "
       "everywhere (smallest gain " + percent (smallest_gain[1]) + ")",
       smallest_gain[1] > 0.0, false},
      {"at speed 1 the gain at the same γ is at least 25% everywhere (the issue's target for fast "
       "motion)",
       smallest_gain[1] >= 0.25, false},
  };
  if (!options.quick)
    findings.push_back ({"without motion compensation (the paper's graph) the temporal filter loses "
                         "to the static one at speed 1 somewhere (smallest gain " +
                             percent (smallest_paper_gain[1]) + "), and motion compensation "
                             "raises the smallest gain at both speeds (0.25: " +
                             percent (smallest_paper_gain[0]) + " to " + percent (smallest_gain[0]) +
                             ")",
                         smallest_paper_gain[1] < 0.0 && smallest_gain[0] > smallest_paper_gain[0] &&
                             smallest_gain[1] > smallest_paper_gain[1],
                         false});
  if (kinect)
    findings.push_back ({"on the fixed Kinect's frames, Tikhonov on the temporal graph leaves consecutive "
                         "frames closer (median) than the raw frames and than the static filter frame by frame",
                         temporal_median < raw_median && temporal_median < per_frame_median, false});
  if (kinect)
    findings.push_back ({"on the fixed Kinect's frames, motion compensation leaves consecutive frames "
                         "further apart than the default temporal filter (it takes the sensor's "
                         "frame-to-frame correlated noise for motion and keeps it)",
                         compensated_median > temporal_median, false});
  return reportFindings (findings, md);
}

} // namespace evaluation
} // namespace pcl_graph_denoise

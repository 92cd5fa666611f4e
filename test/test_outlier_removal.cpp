/*
 * pcl_graph_denoise: graph-signal-processing point cloud denoising for PCL.
 * SPDX-License-Identifier: BSD-3-Clause
 *
 * GraphDegreeOutlierRemoval: the pcl::FilterIndices contract, over several point
 * types, and bad input.
 */
#include <pcl_graph_denoise/graph_degree_outlier_removal.h>

#include <pcl_graph_denoise/point_cloud_adaptor.h>

#include "synthetic.h"
#include "test_clouds.h"

#include <gtest/gtest.h>

#include <pcl/common/io.h>
#include <pcl/filters/filter.h>
#include <pcl/filters/radius_outlier_removal.h>

#include <algorithm>
#include <array>
#include <cstring>
#include <limits>
#include <random>
#include <set>

using pcl_graph_denoise::GraphDegreeOutlierRemoval;
using namespace pcl_graph_denoise::testing;

namespace {

/** A noisy sphere of 3000 points with 60 uniform outliers around it. */
template <typename PointT>
typename pcl::PointCloud<PointT>::Ptr
sphereWithOutliers (std::vector<bool> *truth = nullptr)
{
  auto xyz = pcl_graph_denoise::synthetic::noisySphere (3000, 1.0, 0.005, 1);
  std::vector<bool> outliers = pcl_graph_denoise::synthetic::addUniformOutliers (xyz, 0.02, 0.5, 2);
  if (truth)
    *truth = outliers;
  return withFields<PointT> (xyz);
}

/** Distance of a point to the unit sphere the test clouds are sampled on. */
template <typename PointT>
float
offSphere (const PointT &p)
{
  return std::abs (p.getVector3fMap ().norm () - 1.0f);
}

} // namespace

template <typename PointT>
class OutlierRemovalContract : public ::testing::Test
{
protected:
  using Cloud = pcl::PointCloud<PointT>;
  std::vector<bool> truth;  // declared first: initialised before the cloud
  typename Cloud::Ptr cloud = sphereWithOutliers<PointT> (&truth);
};

using PointTypes = ::testing::Types<pcl::PointXYZ, pcl::PointXYZRGB, pcl::PointNormal>;
TYPED_TEST_SUITE (OutlierRemovalContract, PointTypes);

TYPED_TEST (OutlierRemovalContract, RemovesOutliersKeepsTheSurfaceWithDefaults)
{
  GraphDegreeOutlierRemoval<TypeParam> filter (true);
  filter.setInputCloud (this->cloud);
  pcl::Indices kept;
  filter.filter (kept);
  // Every outlier more than about 2.5 point spacings (0.2) off the surface goes; one
  // landing closer has as many close neighbours as a surface point and cannot be told
  // from one by its degree. The surface stays.
  std::size_t kept_far_outliers = 0, kept_surface = 0;
  for (auto i : kept)
  {
    if (!this->truth[i])
      ++kept_surface;
    else
      kept_far_outliers += offSphere ((*this->cloud)[i]) > 0.2f;
  }
  EXPECT_EQ (kept_far_outliers, 0u);
  EXPECT_GE (kept_surface, 2990u);
  EXPECT_EQ (kept.size () + filter.getRemovedIndices ()->size (), this->cloud->size ());
  EXPECT_GT (filter.getUsedRadius (), 0.0);
  EXPECT_GT (filter.getUsedSigma (), 0.0);
}

TYPED_TEST (OutlierRemovalContract, OutputPointsAreCopiesWithEveryField)
{
  const auto before = deepCopy (*this->cloud);
  GraphDegreeOutlierRemoval<TypeParam> filter;
  filter.setInputCloud (this->cloud);
  pcl::Indices kept;
  filter.filter (kept);
  pcl::PointCloud<TypeParam> out;
  filter.filter (out);
  ASSERT_EQ (out.size (), kept.size ());
  for (std::size_t r = 0; r < kept.size (); ++r)
    ASSERT_TRUE (samePoint (out[r], (*this->cloud)[kept[r]]));
  EXPECT_TRUE (sameCloud (*this->cloud, before));  // input never modified
  EXPECT_TRUE (out.is_dense);
  EXPECT_EQ (out.header.frame_id, this->cloud->header.frame_id);
}

TYPED_TEST (OutlierRemovalContract, KeptIndicesKeepInputOrder)
{
  GraphDegreeOutlierRemoval<TypeParam> filter;
  filter.setInputCloud (this->cloud);
  pcl::Indices kept;
  filter.filter (kept);
  EXPECT_TRUE (std::is_sorted (kept.begin (), kept.end ()));
}

TYPED_TEST (OutlierRemovalContract, NegativeGivesTheComplement)
{
  GraphDegreeOutlierRemoval<TypeParam> filter (true);
  filter.setInputCloud (this->cloud);
  pcl::Indices kept, outliers;
  filter.filter (kept);
  const pcl::Indices removed = *filter.getRemovedIndices ();
  filter.setNegative (true);
  filter.filter (outliers);
  EXPECT_EQ (outliers, removed);
  EXPECT_EQ (*filter.getRemovedIndices (), kept);
}

TYPED_TEST (OutlierRemovalContract, HonoursIndices)
{
  // Only the upper half of the sphere and every other outlier.
  auto indices = std::make_shared<pcl::Indices> ();
  std::size_t surface = 0;
  for (int i = 0; i < static_cast<int> (this->cloud->size ()); ++i)
  {
    const bool upper = !this->truth[i] && (*this->cloud)[i].z > 0.0f;
    if (upper || (this->truth[i] && i % 2 == 0))
      indices->push_back (i);
    surface += upper;
  }
  GraphDegreeOutlierRemoval<TypeParam> filter (true);
  filter.setInputCloud (this->cloud);
  filter.setIndices (indices);
  pcl::Indices kept;
  filter.filter (kept);
  std::set<int> allowed (indices->begin (), indices->end ());
  for (auto i : kept)
    ASSERT_TRUE (allowed.count (i));
  std::set<int> all (kept.begin (), kept.end ());
  for (auto i : *filter.getRemovedIndices ())
  {
    ASSERT_TRUE (allowed.count (i));
    all.insert (i);
  }
  EXPECT_EQ (all, allowed);
  std::size_t kept_far_outliers = 0;
  for (auto i : kept)
    kept_far_outliers += this->truth[i] && offSphere ((*this->cloud)[i]) > 0.2f;
  EXPECT_EQ (kept_far_outliers, 0u);
  EXPECT_GE (double (kept.size ()), 0.99 * double (surface));

  // As in PCL's filters, the indices name the queries and the whole cloud is searched:
  // with the parameters fixed (the derived ones come from the queries), each named point
  // gets the verdict it gets when the whole cloud is filtered. At a threshold of half
  // the lower quartile, the named points along the cut (z = 0) keep their degree through
  // their neighbours below it; filtering the named points alone removes some of them.
  const double tau = 2.5 * filter.getUsedDegreeThreshold ();
  const auto fix = [&] (GraphDegreeOutlierRemoval<TypeParam> &f) {
    f.setRadiusSearch (filter.getUsedRadius ());
    f.setSigma (filter.getUsedSigma ());
    f.setDegreeThreshold (tau);
    f.setResidualThreshold (0.0);
  };
  GraphDegreeOutlierRemoval<TypeParam> named, whole, alone;
  for (auto *f : {&named, &whole})
  {
    f->setInputCloud (this->cloud);
    fix (*f);
  }
  named.setIndices (indices);
  pcl::Indices kept_named, kept_whole, kept_alone;
  named.filter (kept_named);
  whole.filter (kept_whole);
  const std::set<int> whole_set (kept_whole.begin (), kept_whole.end ());
  pcl::Indices expected;
  for (auto i : *indices)
    if (whole_set.count (i))
      expected.push_back (i);
  EXPECT_EQ (kept_named, expected);
  typename pcl::PointCloud<TypeParam>::Ptr subset (new pcl::PointCloud<TypeParam>);
  pcl::copyPointCloud (*this->cloud, *indices, *subset);
  alone.setInputCloud (subset);
  fix (alone);
  alone.filter (kept_alone);
  EXPECT_LT (kept_alone.size (), kept_named.size ());
}

TYPED_TEST (OutlierRemovalContract, KeepOrganizedReplacesRemovedPoints)
{
  GraphDegreeOutlierRemoval<TypeParam> filter;
  filter.setInputCloud (this->cloud);
  pcl::Indices kept;
  filter.filter (kept);
  filter.setKeepOrganized (true);
  filter.setUserFilterValue (-7.0f);
  pcl::PointCloud<TypeParam> out;
  filter.filter (out);
  ASSERT_EQ (out.size (), this->cloud->size ());
  std::set<int> keep (kept.begin (), kept.end ());
  for (std::size_t i = 0; i < out.size (); ++i)
  {
    if (keep.count (static_cast<int> (i)))
      ASSERT_TRUE (samePoint (out[i], (*this->cloud)[i]));
    else
      ASSERT_TRUE (out[i].x == -7.0f && out[i].y == -7.0f && out[i].z == -7.0f);
  }
  filter.setUserFilterValue (std::numeric_limits<float>::quiet_NaN ());
  filter.filter (out);
  EXPECT_FALSE (out.is_dense);
}

TYPED_TEST (OutlierRemovalContract, InPlaceEqualsOutOfPlace)
{
  GraphDegreeOutlierRemoval<TypeParam> filter;
  filter.setInputCloud (this->cloud);
  pcl::PointCloud<TypeParam> out;
  filter.filter (out);
  auto in_place = std::make_shared<pcl::PointCloud<TypeParam>> (deepCopy (*this->cloud));
  filter.setInputCloud (in_place);
  filter.filter (*in_place);
  EXPECT_TRUE (sameCloud (*in_place, out));
}

TYPED_TEST (OutlierRemovalContract, AnIndexListFilteredIntoItselfEqualsACopy)
{
  // setIndices (list); filter (*list): PCL's filters write the kept indices over the list
  // they read; the list was cleared before it was read, and nothing came out (found by a
  // helper's audit).
  auto indices = std::make_shared<pcl::Indices> ();
  for (int i = 0; i < static_cast<int> (this->cloud->size ()); i += 2)
    indices->push_back (i);
  GraphDegreeOutlierRemoval<TypeParam> filter (true);
  filter.setInputCloud (this->cloud);
  filter.setIndices (std::make_shared<pcl::Indices> (*indices));
  pcl::Indices copy;
  filter.filter (copy);
  const pcl::Indices removed = *filter.getRemovedIndices ();
  ASSERT_FALSE (copy.empty ());
  ASSERT_FALSE (removed.empty ());
  filter.setIndices (indices);
  filter.filter (*indices);
  EXPECT_EQ (*indices, copy);
  EXPECT_EQ (*filter.getRemovedIndices (), removed);
}

TYPED_TEST (OutlierRemovalContract, NonFinitePointsAreRemovedAndIgnored)
{
  // Insert NaN and Inf points; the decisions on the finite points must not change.
  auto holes = std::make_shared<pcl::PointCloud<TypeParam>> ();
  pcl::Indices finite_position;
  std::size_t inserted = 0;
  for (std::size_t i = 0; i < this->cloud->size (); ++i)
  {
    if (i % 100 == 0)
    {
      TypeParam bad = (*this->cloud)[i];
      bad.x = (i % 200 == 0) ? std::numeric_limits<float>::quiet_NaN ()
                             : std::numeric_limits<float>::infinity ();
      holes->push_back (bad);
      ++inserted;
    }
    finite_position.push_back (static_cast<int> (holes->size ()));
    holes->push_back ((*this->cloud)[i]);
  }
  GraphDegreeOutlierRemoval<TypeParam> clean, dirty (true);
  clean.setInputCloud (this->cloud);
  dirty.setInputCloud (holes);
  pcl::Indices kept_clean, kept_dirty;
  clean.filter (kept_clean);
  dirty.filter (kept_dirty);
  ASSERT_EQ (kept_clean.size (), kept_dirty.size ());
  for (std::size_t r = 0; r < kept_clean.size (); ++r)
    EXPECT_EQ (finite_position[kept_clean[r]], kept_dirty[r]);
  // Non-finite points are removed in negative mode too, and reported as removed.
  dirty.setNegative (true);
  pcl::Indices outliers;
  dirty.filter (outliers);
  for (auto i : outliers)
    EXPECT_TRUE (pcl_graph_denoise::isFinitePosition ((*holes)[i]));
  std::size_t non_finite_removed = 0;
  for (auto i : *dirty.getRemovedIndices ())
    non_finite_removed += !pcl_graph_denoise::isFinitePosition ((*holes)[i]);
  EXPECT_EQ (non_finite_removed, inserted);
}

TYPED_TEST (OutlierRemovalContract, ResultDoesNotDependOnThreadCount)
{
  GraphDegreeOutlierRemoval<TypeParam> filter;
  filter.setInputCloud (this->cloud);
  pcl::Indices one, two;
  filter.setNumberOfThreads (1);
  filter.filter (one);
  filter.setNumberOfThreads (2);
  filter.filter (two);
  EXPECT_EQ (one, two);
}

TEST (OutlierRemoval, AbsoluteThresholdIsApplied)
{
  auto cloud = sphereWithOutliers<pcl::PointXYZ> ();
  GraphDegreeOutlierRemoval<pcl::PointXYZ> filter;
  filter.setInputCloud (cloud);
  pcl::Indices automatic, strict, none;
  filter.filter (automatic);
  const double tau = filter.getUsedDegreeThreshold ();
  EXPECT_GT (tau, 0.0);
  filter.setDegreeThreshold (0.0);  // nothing has a degree below zero
  EXPECT_EQ (filter.getThresholdRule (), filter.ABSOLUTE_THRESHOLD);
  filter.setResidualThreshold (0.0);  // and the residual test is off
  filter.filter (none);
  EXPECT_EQ (none.size (), cloud->size ());
  filter.setResidualThreshold (4.0);
  filter.setDegreeThreshold (1e9);  // everything is below
  filter.filter (strict);
  EXPECT_TRUE (strict.empty ());
  filter.setDegreeThreshold (tau);
  pcl::Indices same;
  filter.filter (same);
  EXPECT_EQ (same, automatic);
}

TEST (OutlierRemoval, AutomaticThresholdWithMoreThanAQuarterIsolated)
{
  // 300 uniform outliers around a 400-point plane: more than a quarter of the points have
  // no neighbour within epsilon, the first quartile of the degrees is 0, and a threshold
  // of 0 removed nothing (regression). The others' quartile sets it, with a warning.
  std::mt19937 rng (2);
  std::uniform_real_distribution<float> u (-1.0f, 1.0f);
  auto cloud = std::make_shared<pcl::PointCloud<pcl::PointXYZ>> ();
  for (int i = 0; i < 400; ++i)
    cloud->push_back (pcl::PointXYZ (0.01f * float (i % 20), 0.01f * float (i / 20), 0.0f));
  for (int i = 0; i < 300; ++i)
    cloud->push_back (pcl::PointXYZ (u (rng), u (rng), u (rng)));
  GraphDegreeOutlierRemoval<pcl::PointXYZ> filter (true);
  filter.setInputCloud (cloud);
  pcl::Indices kept;
  ::testing::internal::CaptureStderr ();
  filter.filter (kept);
  const std::string err = ::testing::internal::GetCapturedStderr ();
  EXPECT_NE (err.find ("more than a quarter"), std::string::npos) << err;
  EXPECT_GT (filter.getUsedDegreeThreshold (), 0.0);
  std::size_t plane = 0, outliers = 0;
  for (const auto i : kept)
    (i < 400 ? plane : outliers) += 1;
  EXPECT_GE (plane, 390u);
  EXPECT_LE (outliers, 5u);
  // A ratio of 0 still means no threshold, and no warning.
  filter.setAutomaticThresholdRatio (0.0);
  filter.setResidualThreshold (0.0);
  ::testing::internal::CaptureStderr ();
  filter.filter (kept);
  EXPECT_EQ (::testing::internal::GetCapturedStderr (), "");
  EXPECT_EQ (kept.size (), cloud->size ());
}

TEST (OutlierRemoval, KeepsAFloorThatRecedesFromTheScanner)
{
  // A scanner's floor grows sparser with the range, up to 11 times: the degree test alone
  // removes most of its far half; by default the filter keeps it, and the outliers above
  // still go.
  std::vector<FloorPart> parts;
  const auto cloud = std::make_shared<pcl::PointCloud<pcl::PointXYZ>> (recedingFloor (300, 9, parts));
  const auto tally = [&] (const pcl::Indices &kept) {
    std::array<std::size_t, 3> count = {0, 0, 0};
    for (const auto i : kept)
      ++count[static_cast<std::size_t> (parts[i])];
    return count;
  };
  std::array<std::size_t, 3> total = {0, 0, 0};
  for (const FloorPart part : parts)
    ++total[static_cast<std::size_t> (part)];
  GraphDegreeOutlierRemoval<pcl::PointXYZ> filter (true);
  EXPECT_TRUE (filter.getKeepSparseSurfaces ());
  filter.setInputCloud (cloud);
  pcl::Indices kept;
  filter.filter (kept);
  const auto with = tally (kept);
  const std::size_t far = total[1];
  EXPECT_GE (with[0], total[0] - total[0] / 100);
  EXPECT_GE (with[1], far - far / 50);
  EXPECT_EQ (with[2], 0u);
  const double threshold = filter.getUsedDegreeThreshold ();

  filter.setKeepSparseSurfaces (false);
  EXPECT_FALSE (filter.getKeepSparseSurfaces ());
  filter.filter (kept);
  const auto without = tally (kept);
  EXPECT_LT (without[1], far / 2);
  EXPECT_EQ (without[2], 0u);
  EXPECT_EQ (filter.getUsedDegreeThreshold (), threshold);

  // The caller's own threshold is applied as it is: the same threshold as an absolute
  // one removes what the automatic rule without the growth removes.
  filter.setKeepSparseSurfaces (true);
  filter.setDegreeThreshold (threshold);
  pcl::Indices absolute;
  filter.filter (absolute);
  EXPECT_EQ (absolute, kept);
}

TEST (OutlierRemoval, OutlierFractionRemovesThatManyLowestDegreePoints)
{
  std::vector<bool> truth;
  auto cloud = sphereWithOutliers<pcl::PointXYZ> (&truth);
  GraphDegreeOutlierRemoval<pcl::PointXYZ> filter (true);
  filter.setInputCloud (cloud);
  filter.setOutlierFraction (0.10);
  pcl::Indices kept;
  filter.filter (kept);
  const auto n = cloud->size ();
  EXPECT_EQ (filter.getRemovedIndices ()->size (), static_cast<std::size_t> (std::llround (0.1 * n)));
  // The 60 true outliers have the lowest degrees, so all are among the removed.
  std::size_t removed_outliers = 0;
  for (auto i : *filter.getRemovedIndices ())
    removed_outliers += truth[i];
  EXPECT_EQ (removed_outliers, 60u);
  filter.setOutlierFraction (0.0);
  filter.filter (kept);
  EXPECT_EQ (kept.size (), n);
  filter.setOutlierFraction (1.0);
  filter.filter (kept);
  EXPECT_TRUE (kept.empty ());
}

TEST (OutlierRemoval, OutlierFractionRemovesTheMostIsolatedAmongEqualDegrees)
{
  // A dense grid and six far points, each alone (degree 0 in the radius graph): a
  // fraction that removes three must take the three farthest from everything, whatever
  // their place in the cloud (here the nearest three come first).
  auto cloud = std::make_shared<pcl::PointCloud<pcl::PointXYZ>> ();
  for (const float distance : {5.f, 10.f, 15.f, 20.f, 40.f, 80.f})
    cloud->push_back (pcl::PointXYZ (distance, distance, distance));
  for (int i = 0; i < 30; ++i)
    for (int j = 0; j < 30; ++j)
      cloud->push_back (pcl::PointXYZ (0.01f * i, 0.01f * j, 0.0f));
  GraphDegreeOutlierRemoval<pcl::PointXYZ> filter (true);
  filter.setInputCloud (cloud);
  filter.setOutlierFraction (3.0 / double (cloud->size ()));
  pcl::Indices kept;
  filter.filter (kept);
  pcl::Indices removed = *filter.getRemovedIndices ();
  std::sort (removed.begin (), removed.end ());
  EXPECT_EQ (removed, (pcl::Indices{3, 4, 5}));
  EXPECT_EQ (filter.getUsedDegreeThreshold (), 0.0);
}

namespace {

/** F1 score of `removed` as the outliers `truth` marks. */
double
f1Score (const pcl::Indices &removed, const std::vector<bool> &truth)
{
  std::size_t hits = 0;
  for (auto i : removed)
    hits += truth[i];
  const auto outliers = static_cast<std::size_t> (std::count (truth.begin (), truth.end (), true));
  return removed.empty () ? 0.0 : 2.0 * double (hits) / double (removed.size () + outliers);
}

} // namespace

TEST (OutlierRemoval, ResidualTestRemovesTheOutliersCloseToTheSurface)
{
  // 20,000 points on a unit sphere, noise 0.2% of its radius, 5% uniform outliers in its
  // bounding box: about a tenth of them land within two spacings of the surface, where
  // their degree is an inlier's (and 2.5% within 4 noise levels, where nothing can tell).
  auto cloud = std::make_shared<pcl::PointCloud<pcl::PointXYZ>> (
      pcl_graph_denoise::synthetic::noisySphere (20000, 1.0, 0.002, 41));
  const std::vector<bool> truth = pcl_graph_denoise::synthetic::addUniformOutliers (*cloud, 0.05, 0.0, 42);
  GraphDegreeOutlierRemoval<pcl::PointXYZ> filter (true);
  EXPECT_EQ (filter.getResidualThreshold (), 4.0);
  filter.setInputCloud (cloud);
  pcl::Indices kept;
  filter.filter (kept);
  const pcl::Indices with_test = *filter.getRemovedIndices ();
  filter.setResidualThreshold (0.0);  // the degree test alone, as the paper
  filter.filter (kept);
  const pcl::Indices degree_only = *filter.getRemovedIndices ();
  const double f1 = f1Score (with_test, truth), f1_degree = f1Score (degree_only, truth);
  EXPECT_GE (f1, 0.97) << "the degree test alone: " << f1_degree;
  EXPECT_GT (f1, f1_degree + 0.01);
  // The residual test only adds to what the degree test removes.
  const std::set<pcl::index_t> more (with_test.begin (), with_test.end ());
  for (auto i : degree_only)
    EXPECT_EQ (more.count (i), 1u) << i;
  // What it adds are outliers off the surface by more than a few noise levels.
  std::size_t added_inliers = 0;
  for (auto i : with_test)
    added_inliers += !truth[i];
  EXPECT_LE (added_inliers, 10u);
}

TEST (OutlierRemoval, ResidualTestKeepsSharpEdgesAndCorners)
{
  // A noiseless and a nearly noiseless cube: every point of its edges and corners is off
  // its neighbours' plane, as they all are; none is removed.
  for (const double noise : {0.0, 0.0005})
  {
    auto cube = std::make_shared<pcl::PointCloud<pcl::PointXYZ>> (
        pcl_graph_denoise::synthetic::noisyCube (30000, noise, 43));
    GraphDegreeOutlierRemoval<pcl::PointXYZ> filter (true);
    filter.setInputCloud (cube);
    pcl::Indices kept;
    filter.filter (kept);
    EXPECT_EQ (kept.size (), cube->size ()) << "noise " << noise;
  }
}

TEST (OutlierRemoval, OutlierFractionIgnoresTheResidualTest)
{
  // The fraction rule removes exactly that count, by degree, whatever the residual test.
  auto cloud = sphereWithOutliers<pcl::PointXYZ> ();
  GraphDegreeOutlierRemoval<pcl::PointXYZ> filter (true);
  filter.setInputCloud (cloud);
  filter.setOutlierFraction (0.05);
  pcl::Indices a, b;
  filter.filter (a);
  filter.setResidualThreshold (1.0);  // would remove more points if it applied
  filter.filter (b);
  EXPECT_EQ (a, b);
  // The automatic rule applies it.
  filter.setAutomaticThresholdRatio (0.2);
  pcl::Indices with_test, without;
  filter.filter (with_test);
  filter.setResidualThreshold (0.0);
  filter.filter (without);
  EXPECT_LT (with_test.size (), without.size ());
}

TEST (OutlierRemoval, UnitInvariantDefaults)
{
  auto metres = sphereWithOutliers<pcl::PointXYZ> ();
  auto millimetres = std::make_shared<pcl::PointCloud<pcl::PointXYZ>> (*metres);
  for (auto &p : *millimetres)
    p.getVector3fMap () *= 1000.0f;
  GraphDegreeOutlierRemoval<pcl::PointXYZ> filter;
  pcl::Indices a, b;
  filter.setInputCloud (metres);
  filter.filter (a);
  const double radius = filter.getUsedRadius ();
  filter.setInputCloud (millimetres);
  filter.filter (b);
  EXPECT_EQ (a, b);
  EXPECT_NEAR (filter.getUsedRadius (), 1000.0 * radius, 1e-3 * filter.getUsedRadius ());
}

TEST (OutlierRemoval, ExplicitRadiusAndSigmaAreUsed)
{
  auto cloud = sphereWithOutliers<pcl::PointXYZ> ();
  GraphDegreeOutlierRemoval<pcl::PointXYZ> filter;
  filter.setInputCloud (cloud);
  filter.setRadiusSearch (0.2);
  filter.setSigma (0.05);
  pcl::Indices kept;
  filter.filter (kept);
  EXPECT_EQ (filter.getUsedRadius (), 0.2);
  EXPECT_EQ (filter.getUsedSigma (), 0.05);
  EXPECT_EQ (filter.getRadiusSearch (), 0.2);
  EXPECT_EQ (filter.getSigma (), 0.05);
}

TEST (OutlierRemoval, WorksThroughAFilterPointer)
{
  auto cloud = sphereWithOutliers<pcl::PointXYZ> ();
  pcl::Filter<pcl::PointXYZ>::Ptr filter (new GraphDegreeOutlierRemoval<pcl::PointXYZ>);
  filter->setInputCloud (cloud);
  pcl::PointCloud<pcl::PointXYZ> out;
  filter->filter (out);
  EXPECT_GE (out.size (), 2990u);
  EXPECT_LE (out.size (), 3002u);
}

// ---- Bad input ---------------------------------------------------------------------

namespace {

/** Runs the filter on `cloud`, capturing what it printed on stderr. */
std::string
runCapturing (GraphDegreeOutlierRemoval<pcl::PointXYZ> &filter,
              const pcl::PointCloud<pcl::PointXYZ>::Ptr &cloud, pcl::Indices &kept)
{
  filter.setInputCloud (cloud);
  ::testing::internal::CaptureStderr ();
  filter.filter (kept);
  return ::testing::internal::GetCapturedStderr ();
}

} // namespace

TEST (OutlierRemovalBadInput, EmptyCloud)
{
  auto cloud = std::make_shared<pcl::PointCloud<pcl::PointXYZ>> ();
  GraphDegreeOutlierRemoval<pcl::PointXYZ> filter (true);
  pcl::Indices kept{1, 2};
  const std::string err = runCapturing (filter, cloud, kept);
  EXPECT_TRUE (kept.empty ());
  EXPECT_NE (err.find ("GraphDegreeOutlierRemoval"), std::string::npos) << err;
  pcl::PointCloud<pcl::PointXYZ> out;
  filter.filter (out);
  EXPECT_TRUE (out.empty ());
}

TEST (OutlierRemovalBadInput, AllNaNCloud)
{
  auto cloud = std::make_shared<pcl::PointCloud<pcl::PointXYZ>> ();
  for (int i = 0; i < 10; ++i)
    cloud->push_back (pcl::PointXYZ (std::numeric_limits<float>::quiet_NaN (), 0.0f, 0.0f));
  const auto before = deepCopy (*cloud);
  GraphDegreeOutlierRemoval<pcl::PointXYZ> filter (true);
  pcl::Indices kept;
  const std::string err = runCapturing (filter, cloud, kept);
  EXPECT_TRUE (kept.empty ());
  EXPECT_EQ (filter.getRemovedIndices ()->size (), 10u);
  EXPECT_NE (err.find ("no finite point"), std::string::npos) << err;
  EXPECT_TRUE (sameCloud (*cloud, before));
}

TEST (OutlierRemovalBadInput, ARadiusOrSigmaTooSmallForTheCloudWarns)
{
  // A sphere in millimetres given parameters in metres: no point has a neighbour within
  // 0.05, or every weight underflows at theta 0.02. No threshold can be derived; the
  // filter says so instead of returning the cloud without a word.
  auto cloud = std::make_shared<pcl::PointCloud<pcl::PointXYZ>> (
      pcl_graph_denoise::synthetic::noisySphere (3000, 1000.0, 5.0, 4));
  for (const bool radius : {true, false})
  {
    GraphDegreeOutlierRemoval<pcl::PointXYZ> filter;
    if (radius)
      filter.setRadiusSearch (0.05);
    else
      filter.setSigma (0.02);
    pcl::Indices kept;
    const std::string err = runCapturing (filter, cloud, kept);
    EXPECT_NE (err.find ("None of the 3000 points has a neighbour"), std::string::npos) << err;
    EXPECT_NE (err.find (radius ? "epsilon = 0.05" : "theta = 0.02"), std::string::npos) << err;
    EXPECT_EQ (filter.getUsedDegreeThreshold (), 0.0);
  }
  // At the derived values: no such warning.
  GraphDegreeOutlierRemoval<pcl::PointXYZ> filter;
  pcl::Indices kept;
  EXPECT_EQ (runCapturing (filter, cloud, kept).find ("None of the"), std::string::npos);
}

TEST (OutlierRemovalBadInput, OnePointAndTwoPoints)
{
  auto cloud = std::make_shared<pcl::PointCloud<pcl::PointXYZ>> ();
  cloud->push_back (pcl::PointXYZ (1.0f, 2.0f, 3.0f));
  GraphDegreeOutlierRemoval<pcl::PointXYZ> filter;
  pcl::Indices kept;
  filter.setInputCloud (cloud);
  filter.filter (kept);
  EXPECT_EQ (kept, pcl::Indices{0});  // nothing to compare it with: kept
  cloud->push_back (pcl::PointXYZ (1.0f, 2.0f, 4.0f));
  filter.filter (kept);
  EXPECT_EQ (kept, (pcl::Indices{0, 1}));
}

TEST (OutlierRemovalBadInput, FewerPointsThanNeighboursAndDuplicates)
{
  auto cloud = std::make_shared<pcl::PointCloud<pcl::PointXYZ>> ();
  for (int i = 0; i < 4; ++i)
    cloud->push_back (pcl::PointXYZ (0.1f * i, 0.0f, 0.0f));
  for (int i = 0; i < 4; ++i)  // every point twice
    cloud->push_back ((*cloud)[i]);
  GraphDegreeOutlierRemoval<pcl::PointXYZ> filter;
  pcl::Indices kept;
  filter.setInputCloud (cloud);
  filter.filter (kept);
  EXPECT_EQ (kept.size (), 8u);
  // All points identical: zero spacing, nothing to single out, nothing removed.
  auto same = std::make_shared<pcl::PointCloud<pcl::PointXYZ>> ();
  same->resize (50, pcl::PointXYZ (4.0f, 5.0f, 6.0f));
  filter.setInputCloud (same);
  filter.filter (kept);
  EXPECT_EQ (kept.size (), 50u);
}

TEST (OutlierRemovalBadInput, HeavilyDuplicatedCloudIsMeasuredOnItsDistinctPositions)
{
  // A 30 x 30 grid of spacing 0.01, every point 12 times, and two far points: every
  // point's 10 nearest neighbours are its copies, so the median spacing is 0; measured
  // on the distinct positions it is the grid's, and the far points go.
  auto grid = std::make_shared<pcl::PointCloud<pcl::PointXYZ>> ();
  for (int i = 0; i < 30; ++i)
    for (int j = 0; j < 30; ++j)
      grid->push_back (pcl::PointXYZ (0.01f * i, 0.01f * j, 0.0f));
  auto copies = std::make_shared<pcl::PointCloud<pcl::PointXYZ>> ();
  for (int c = 0; c < 12; ++c)
    *copies += *grid;
  copies->push_back (pcl::PointXYZ (1.0f, 1.0f, 1.0f));
  copies->push_back (pcl::PointXYZ (-1.0f, 2.0f, 0.5f));
  GraphDegreeOutlierRemoval<pcl::PointXYZ> filter (true);
  filter.setInputCloud (copies);
  pcl::Indices kept;
  filter.filter (kept);
  EXPECT_EQ (kept.size (), copies->size () - 2);
  const pcl::Indices far = {static_cast<int> (copies->size ()) - 2,
                            static_cast<int> (copies->size ()) - 1};
  EXPECT_EQ (*filter.getRemovedIndices (), far);
  // The same radius as for the grid alone (plus the far points).
  grid->push_back (copies->back ());
  grid->push_back ((*copies)[copies->size () - 2]);
  GraphDegreeOutlierRemoval<pcl::PointXYZ> single;
  single.setInputCloud (grid);
  single.filter (kept);
  EXPECT_GT (filter.getUsedRadius (), 0.0);
  EXPECT_NEAR (filter.getUsedRadius (), single.getUsedRadius (), 1e-6 * single.getUsedRadius ());
}

TEST (OutlierRemovalBadInput, FewerDistinctPositionsThanNeighboursEndTheSparseSurfaceSearch)
{
  // Three close positions ten times each and a far one twice: the far pair falls below the
  // threshold, and the search for its 10 nearest distinct positions, which finds only
  // three in the whole cloud, must end (it ran forever: a fuzzer's input).
  auto cloud = std::make_shared<pcl::PointCloud<pcl::PointXYZ>> ();
  for (int copy = 0; copy < 10; ++copy)
  {
    cloud->push_back (pcl::PointXYZ (0.0f, 0.0f, 0.0f));
    cloud->push_back (pcl::PointXYZ (0.1f, 0.0f, 0.0f));
    cloud->push_back (pcl::PointXYZ (0.0f, 0.1f, 0.0f));
  }
  cloud->push_back (pcl::PointXYZ (100.0f, 0.0f, 0.0f));
  cloud->push_back (pcl::PointXYZ (100.0f, 0.0f, 0.0f));
  GraphDegreeOutlierRemoval<pcl::PointXYZ> filter (true);
  filter.setInputCloud (cloud);
  pcl::Indices kept;
  filter.filter (kept);
  EXPECT_GT (filter.getUsedDegreeThreshold (), 1.0);  // the far pair is a candidate
  EXPECT_EQ (kept.size (), 30u);
  EXPECT_EQ (*filter.getRemovedIndices (), (pcl::Indices{30, 31}));
}

TEST (OutlierRemovalBadInput, ACopiedCloudKeepsTheResidualTestsDecisions)
{
  // A noisy plane and a point two spacings above it: linked to the plane, so only the
  // residual test removes it. The whole cloud twice or three times over: the point's
  // copies lay beside it and passed for a layer of surface points with it (its plane
  // counted them), so every copy was kept; the plane leaves out its own copies.
  auto plane = std::make_shared<pcl::PointCloud<pcl::PointXYZ>> ();
  std::mt19937 rng (5);
  std::normal_distribution<float> noise (0.0f, 0.001f);
  for (int i = 0; i < 100; ++i)
    for (int j = 0; j < 100; ++j)
      plane->push_back (pcl::PointXYZ (0.01f * i, 0.01f * j, noise (rng)));
  plane->push_back (pcl::PointXYZ (0.505f, 0.505f, 0.02f));
  const int above = static_cast<int> (plane->size ()) - 1;
  GraphDegreeOutlierRemoval<pcl::PointXYZ> filter (true);
  pcl::Indices kept;
  filter.setInputCloud (plane);
  filter.filter (kept);
  const std::size_t kept_once = kept.size ();
  ASSERT_EQ (*filter.getRemovedIndices (), pcl::Indices{above});
  for (const int times : {2, 3})
  {
    auto cloud = std::make_shared<pcl::PointCloud<pcl::PointXYZ>> ();
    for (int t = 0; t < times; ++t)
      *cloud += *plane;
    filter.setInputCloud (cloud);
    filter.filter (kept);
    pcl::Indices expected;
    for (int t = 0; t < times; ++t)
      expected.push_back (above + t * static_cast<int> (plane->size ()));
    EXPECT_EQ (*filter.getRemovedIndices (), expected) << times << " times";
    EXPECT_EQ (kept.size (), times * kept_once) << times << " times";
  }
}

TEST (OutlierRemovalBadInput, AStackOfCopiesChangesNothingElse)
{
  // A sphere 2 units from the origin and, as some drivers store invalid returns, up to
  // twice as many copies of (0, 0, 0). The copies make no surface denser: the radius and
  // the sphere's points kept are those of the sphere alone (the stack lowered the
  // median spacing: with 4,900 copies the radius fell from 0.185 to 0.114 and 63 sphere
  // points went), and the stack, each copy with the others as neighbours, is kept as
  // RadiusOutlierRemoval keeps it. Each position is searched once: 10,000 copies were
  // 10,000 searches listing 9,999 copies each.
  auto sphere = std::make_shared<pcl::PointCloud<pcl::PointXYZ>> (
      pcl_graph_denoise::synthetic::noisySphere (5000, 1.0, 0.005, 9));
  for (auto &p : *sphere)
    p.z += 2.0f;
  GraphDegreeOutlierRemoval<pcl::PointXYZ> alone;
  alone.setInputCloud (sphere);
  pcl::Indices kept_alone;
  alone.filter (kept_alone);
  for (const int copies : {4900, 10000})
  {
    auto cloud = std::make_shared<pcl::PointCloud<pcl::PointXYZ>> (*sphere);
    cloud->resize (sphere->size () + copies, pcl::PointXYZ (0.0f, 0.0f, 0.0f));
    GraphDegreeOutlierRemoval<pcl::PointXYZ> filter;
    filter.setInputCloud (cloud);
    pcl::Indices kept;
    filter.filter (kept);
    EXPECT_NEAR (filter.getUsedRadius (), alone.getUsedRadius (), 1e-6 * alone.getUsedRadius ())
        << copies << " copies";
    const auto sphere_end = std::lower_bound (kept.begin (), kept.end (), int (sphere->size ()));
    EXPECT_LE (kept_alone.size () - std::size_t (sphere_end - kept.begin ()), 5u) << copies << " copies";
    EXPECT_EQ (std::size_t (kept.end () - sphere_end), std::size_t (copies)) << copies << " copies";
  }
}

TEST (OutlierRemovalBadInput, InvalidParametersAreNamed)
{
  auto cloud = sphereWithOutliers<pcl::PointXYZ> ();
  const auto before = deepCopy (*cloud);
  struct Case
  {
    std::function<void (GraphDegreeOutlierRemoval<pcl::PointXYZ> &)> set;
    std::string parameter;
  };
  const double nan = std::numeric_limits<double>::quiet_NaN ();
  const double inf = std::numeric_limits<double>::infinity ();
  const std::vector<Case> cases = {
      {[] (auto &f) { f.setRadiusSearch (-1.0); }, "radius"},
      {[&] (auto &f) { f.setRadiusSearch (nan); }, "radius"},
      {[&] (auto &f) { f.setRadiusSearch (inf); }, "radius"},
      {[] (auto &f) { f.setSigma (-0.1); }, "sigma"},
      {[&] (auto &f) { f.setSigma (nan); }, "sigma"},
      {[] (auto &f) { f.setDegreeThreshold (-1.0); }, "degree threshold"},
      {[&] (auto &f) { f.setDegreeThreshold (nan); }, "degree threshold"},
      {[] (auto &f) { f.setOutlierFraction (1.5); }, "outlier fraction"},
      {[&] (auto &f) { f.setOutlierFraction (nan); }, "outlier fraction"},
      {[] (auto &f) { f.setAutomaticThresholdRatio (-2.0); }, "threshold ratio"},
      {[] (auto &f) { f.setResidualThreshold (-1.0); }, "residual multiplier"},
      {[&] (auto &f) { f.setResidualThreshold (nan); }, "residual multiplier"},
      {[&] (auto &f) { f.setResidualThreshold (inf); }, "residual multiplier"},
      {[] (auto &f) { f.setNumberOfThreads (-1); }, "number of threads"},
  };
  for (const auto &c : cases)
  {
    GraphDegreeOutlierRemoval<pcl::PointXYZ> filter (true);
    c.set (filter);
    pcl::Indices kept{5};
    const std::string err = runCapturing (filter, cloud, kept);
    EXPECT_TRUE (kept.empty ()) << c.parameter;
    EXPECT_TRUE (filter.getRemovedIndices ()->empty ()) << c.parameter;
    EXPECT_NE (err.find ("GraphDegreeOutlierRemoval"), std::string::npos) << err;
    EXPECT_NE (err.find (c.parameter), std::string::npos) << err;
    pcl::PointCloud<pcl::PointXYZ> out;
    filter.filter (out);
    EXPECT_TRUE (out.empty ());
    // The shape of PCL's own filters' error path (RadiusOutlierRemoval without a radius),
    // with and without setKeepOrganized (which would otherwise return the whole input).
    for (const bool organized : {false, true})
    {
      filter.setKeepOrganized (organized);
      pcl::PointCloud<pcl::PointXYZ> failed;
      failed.resize (7);
      filter.filter (failed);
      EXPECT_EQ (failed.size (), 0u) << c.parameter;
      EXPECT_EQ (failed.width, 0u) << c.parameter;
      EXPECT_EQ (failed.height, 1u) << c.parameter;
      EXPECT_EQ (failed.is_dense, cloud->is_dense) << c.parameter;
      EXPECT_EQ (failed.header.frame_id, cloud->header.frame_id) << c.parameter;
    }
  }
  EXPECT_TRUE (sameCloud (*cloud, before));
  // The reference: PCL's RadiusOutlierRemoval with no radius set.
  pcl::RadiusOutlierRemoval<pcl::PointXYZ> reference;
  reference.setInputCloud (cloud);
  pcl::PointCloud<pcl::PointXYZ> expected;
  ::testing::internal::CaptureStderr ();
  reference.filter (expected);
  ::testing::internal::GetCapturedStderr ();
  EXPECT_EQ (expected.size (), 0u);
  EXPECT_EQ (expected.width, 0u);
  EXPECT_EQ (expected.height, 1u);
  EXPECT_EQ (expected.is_dense, cloud->is_dense);
}

TEST (OutlierRemovalBadInput, IndicesOutOfRangeOrRepeated)
{
  auto cloud = sphereWithOutliers<pcl::PointXYZ> ();
  GraphDegreeOutlierRemoval<pcl::PointXYZ> filter;
  filter.setIndices (std::make_shared<pcl::Indices> (pcl::Indices{0, 1, 100000}));
  pcl::Indices kept{3};
  std::string err = runCapturing (filter, cloud, kept);
  EXPECT_TRUE (kept.empty ());
  EXPECT_NE (err.find ("out of range"), std::string::npos) << err;
  filter.setIndices (std::make_shared<pcl::Indices> (pcl::Indices{0, -1}));
  err = runCapturing (filter, cloud, kept);
  EXPECT_TRUE (kept.empty ());

  // Repeated indices are used once, at their first place, with a warning.
  auto indices = std::make_shared<pcl::Indices> ();
  for (int i = 0; i < 3000; ++i)
    indices->push_back (i);
  indices->push_back (10);
  filter.setIndices (indices);
  err = runCapturing (filter, cloud, kept);
  EXPECT_EQ (kept.size (), std::set<int> (kept.begin (), kept.end ()).size ());
  EXPECT_GE (kept.size (), 2990u);
  EXPECT_NE (err.find ("repeated"), std::string::npos) << err;
}

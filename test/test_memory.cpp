/*
 * pcl_graph_denoise: graph-signal-processing point cloud denoising for PCL.
 * SPDX-License-Identifier: BSD-3-Clause
 *
 * The memory limit (setMemoryLimit, KnnGraphParams::memory_limit): the estimates grow
 * with what is asked, a cloud above the limit fails up front with a clear error and an
 * empty result and its input untouched, a limit at the estimate changes nothing, and
 * the estimate bounds the peak actually measured.
 */
#include <pcl_graph_denoise/core/graph.h>
#include <pcl_graph_denoise/core/memory.h>
#include <pcl_graph_denoise/graph_degree_outlier_removal.h>
#include <pcl_graph_denoise/graph_tikhonov_smoothing.h>
#include <pcl_graph_denoise/graph_tv_smoothing.h>

#include "peak_memory.h"
#include "synthetic.h"
#include "test_clouds.h"

#include <gtest/gtest.h>

#include <pcl/console/print.h>

#include <cstdint>
#include <limits>
#include <stdexcept>
#include <string>

using namespace pcl_graph_denoise;
using namespace pcl_graph_denoise::testing;

namespace {

using Cloud = pcl::PointCloud<pcl::PointXYZ>;

#if defined(__SANITIZE_ADDRESS__)
constexpr bool kSanitized = true;
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
constexpr bool kSanitized = true;
#else
constexpr bool kSanitized = false;
#endif
#else
constexpr bool kSanitized = false;
#endif

using synthetic::toMatrix;

} // namespace

TEST (Memory, EstimatesGrowWithPointsAndNeighbours)
{
  using core::SmoothingKind;
  for (const auto kind : {SmoothingKind::TIKHONOV, SmoothingKind::TIKHONOV_CHOLMOD,
                          SmoothingKind::TOTAL_VARIATION})
  {
    EXPECT_LT (core::smoothingMemory (1000, 10, kind), core::smoothingMemory (2000, 10, kind));
    EXPECT_LT (core::smoothingMemory (1000, 10, kind), core::smoothingMemory (1000, 20, kind));
    EXPECT_GT (core::smoothingMemory (1000, 10, kind), core::knnGraphMemory (1000, 10));
    // k is capped at N - 1, as the graph does; a huge k or N saturates, never wraps.
    EXPECT_EQ (core::smoothingMemory (100, 99, kind), core::smoothingMemory (100, 1000000, kind));
    EXPECT_EQ (core::smoothingMemory (std::numeric_limits<std::size_t>::max (), 1u << 30, kind),
               std::numeric_limits<std::size_t>::max ());
  }
  EXPECT_LT (core::smoothingMemory (1000, 10, SmoothingKind::TIKHONOV),
             core::smoothingMemory (1000, 10, SmoothingKind::TOTAL_VARIATION));
  EXPECT_LT (core::smoothingMemory (1000, 10, SmoothingKind::TOTAL_VARIATION),
             core::smoothingMemory (1000, 10, SmoothingKind::TIKHONOV_CHOLMOD));
  EXPECT_EQ (core::knnGraphMemory (0, 10), 0u);
  EXPECT_LT (core::radiusDegreesMemory (1000), core::radiusDegreesMemory (2000));
  EXPECT_GT (core::physicalMemory (), std::size_t (1) << 28);  // any machine that runs this

  // The filters add their PCL layer (the output cloud): a larger point type costs more.
  GraphTVSmoothing<pcl::PointXYZ> tv;
  GraphTVSmoothing<pcl::PointXYZRGBNormal> tv_rgbn;
  EXPECT_GT (tv.estimateMemory (1000), core::smoothingMemory (1000, 10, SmoothingKind::TOTAL_VARIATION));
  EXPECT_GT (tv_rgbn.estimateMemory (1000), tv.estimateMemory (1000));
  tv.setKSearch (20);
  EXPECT_GT (tv.estimateMemory (1000), tv_rgbn.estimateMemory (1000));
  GraphTikhonovSmoothing<pcl::PointXYZ> tikhonov;
  const std::size_t cg = tikhonov.estimateMemory (1000);
  tikhonov.setSolver (core::TikhonovSolver::CHOLMOD);
  EXPECT_GT (tikhonov.estimateMemory (1000), cg);
  GraphDegreeOutlierRemoval<pcl::PointXYZ> outliers;
  EXPECT_GT (outliers.estimateMemory (1000), core::radiusDegreesMemory (1000));
}

TEST (Memory, KnnGraphAboveItsLimitIsRefused)
{
  const core::PointMatrix points = toMatrix (synthetic::noisySphere (3000, 1.0, 0.01, 5));
  core::KnnGraphParams params;
  params.memory_limit = core::knnGraphMemory (3000, 10) - 1;
  try
  {
    core::buildKnnGraph (points, params);
    ADD_FAILURE () << "no error below the estimate";
  }
  catch (const std::invalid_argument &e)
  {
    EXPECT_NE (std::string (e.what ()).find ("memory limit"), std::string::npos) << e.what ();
    EXPECT_NE (std::string (e.what ()).find ("3000 points"), std::string::npos) << e.what ();
  }
  params.memory_limit = core::knnGraphMemory (3000, 10);
  const core::PointGraph limited = core::buildKnnGraph (points, params);
  const core::PointGraph free = core::buildKnnGraph (points, core::KnnGraphParams{});
  EXPECT_EQ (limited.col, free.col);
  EXPECT_EQ (limited.weight, free.weight);
}

TEST (Memory, FiltersAboveTheirLimitFailUpFrontAndAtItChangeNothing)
{
  pcl::console::setVerbosityLevel (pcl::console::L_ALWAYS);
  const auto cloud = withFields<pcl::PointXYZRGB> (synthetic::noisySphere (3000, 1.0, 0.02, 6));
  const auto copy = deepCopy (*cloud);
  const std::size_t n = cloud->size ();

  GraphTikhonovSmoothing<pcl::PointXYZRGB> tikhonov;
  GraphTVSmoothing<pcl::PointXYZRGB> tv;
  for (GraphSmoothing<pcl::PointXYZRGB> *filter :
       {static_cast<GraphSmoothing<pcl::PointXYZRGB> *> (&tikhonov),
        static_cast<GraphSmoothing<pcl::PointXYZRGB> *> (&tv)})
  {
    const char *name = filter == &tikhonov ? "Tikhonov" : "TV";
    filter->setInputCloud (cloud);
    pcl::PointCloud<pcl::PointXYZRGB> free, limited;
    filter->filter (free);
    ASSERT_EQ (free.size (), n);
    filter->setMemoryLimit (filter->estimateMemory (n) - 1);
    EXPECT_EQ (filter->getMemoryLimit (), filter->estimateMemory (n) - 1);
    filter->filter (limited);
    EXPECT_TRUE (limited.empty ()) << name;
    EXPECT_TRUE (sameCloud (*cloud, copy));
    filter->setMemoryLimit (filter->estimateMemory (n));
    filter->filter (limited);
    EXPECT_TRUE (sameCloud (limited, free)) << name;
    filter->setMemoryLimit (0);  // the machine's memory
    filter->filter (limited);
    EXPECT_TRUE (sameCloud (limited, free)) << name;
  }

  GraphDegreeOutlierRemoval<pcl::PointXYZRGB> outliers (true);
  outliers.setInputCloud (cloud);
  pcl::Indices free, limited;
  outliers.filter (free);
  ASSERT_FALSE (free.empty ());
  outliers.setMemoryLimit (outliers.estimateMemory (n) - 1);
  outliers.filter (limited);
  EXPECT_TRUE (limited.empty ());
  EXPECT_TRUE (outliers.getRemovedIndices ()->empty ());
  pcl::PointCloud<pcl::PointXYZRGB> organised;
  outliers.setKeepOrganized (true);
  outliers.filter (organised);
  EXPECT_TRUE (organised.empty ());
  EXPECT_TRUE (sameCloud (*cloud, copy));
  outliers.setKeepOrganized (false);
  outliers.setMemoryLimit (outliers.estimateMemory (n));
  outliers.filter (limited);
  EXPECT_EQ (limited, free);
}

/** The estimates are upper bounds of the peak the work really reaches, and not wildly
 *  above it (they are what refuses a cloud: too high would refuse clouds that fit). */
TEST (Memory, EstimatesBoundTheMeasuredPeak)
{
  if (kSanitized)
    GTEST_SKIP () << "AddressSanitizer's shadow memory and quarantine change the peak";
  pcl::console::setVerbosityLevel (pcl::console::L_ALWAYS);
  const auto cloud = std::make_shared<Cloud> (synthetic::noisySphere (200000, 1.0, 0.01, 7));
  const std::size_t n = cloud->size ();
  const auto check = [&] (const char *what, const synthetic::PeakMemory &peak) {
    ASSERT_GT (peak.bytes, 0.0) << what << ": no measure (/proc/self/clear_refs)";
    const double estimate = double (peak.returned);
    EXPECT_GE (estimate, peak.bytes) << what << ": estimate " << estimate / n << " bytes/point, peak "
                                     << peak.bytes / n;
    EXPECT_LE (estimate, 2.5 * peak.bytes) << what << ": estimate " << estimate / n
                                           << " bytes/point, peak " << peak.bytes / n;
  };
  check ("GraphTikhonovSmoothing", synthetic::measurePeakMemory ([&] {
           GraphTikhonovSmoothing<pcl::PointXYZ> filter;
           filter.setInputCloud (cloud);
           Cloud out;
           filter.filter (out);
           return out.size () == n ? filter.estimateMemory (n) : 0;
         }));
  check ("GraphTVSmoothing", synthetic::measurePeakMemory ([&] {
           GraphTVSmoothing<pcl::PointXYZ> filter;
           filter.setInputCloud (cloud);
           Cloud out;
           filter.filter (out);
           return out.size () == n ? filter.estimateMemory (n) : 0;
         }));
  check ("GraphDegreeOutlierRemoval", synthetic::measurePeakMemory ([&] {
           GraphDegreeOutlierRemoval<pcl::PointXYZ> filter;
           filter.setInputCloud (cloud);
           Cloud out;
           filter.filter (out);
           return out.empty () ? 0 : filter.estimateMemory (n);
         }));
}

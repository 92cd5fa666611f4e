/*
 * pcl_graph_denoise: graph-signal-processing point cloud denoising for PCL.
 * SPDX-License-Identifier: BSD-3-Clause
 */
#pragma once

#include <pcl_graph_denoise/graph_smoothing.h>

namespace pcl_graph_denoise {

/** \brief Graph total-variation smoothing of point positions (Schoenenberger, Paratte,
 *  Vandergheynst 2015): x = argmin 1/2 |x - f|^2 + gamma sum_e |(grad x)_e| on the k-NN
 *  graph, (grad x)_e = sqrt(w_ij) (x_i - x_j) over each edge once. It keeps sharp edges
 *  where Tikhonov rounds them.
 *
 * The isotropic norm (the Euclidean norm of each edge's 3-vector difference, rotation
 * invariant) is the default; the anisotropic one (the sum of the three absolute
 * differences) is an option. gamma is a length, in the cloud's units; its default is
 * derived from the data (see core::defaultTotalVariationGamma). Solved by the
 * diagonally preconditioned, accelerated primal-dual algorithm of Chambolle and Pock
 * (core::solveTotalVariation), stopped on the relative duality gap. See GraphSmoothing
 * for the parameters and the output contract.
 *
 * \code
 * pcl_graph_denoise::GraphTVSmoothing<pcl::PointXYZ> smoother;
 * smoother.setInputCloud (cloud);
 * smoother.filter (*smoothed);
 * \endcode
 */
template <typename PointT>
class GraphTVSmoothing : public GraphSmoothing<PointT>
{
  using GraphSmoothing<PointT>::filter_name_;

public:
  using Ptr = std::shared_ptr<GraphTVSmoothing<PointT>>;  ///< shared pointer, as PCL's filters
  using ConstPtr = std::shared_ptr<const GraphTVSmoothing<PointT>>;  ///< shared pointer to const

  /** \brief The default tolerance where quadrics are fitted (setTolerance): on the
   *  calibration set 0.2% less error than the solver's 1e-3 at 1e-2 (geometric mean), at
   *  most 0.7% more on any cloud; 2e-2 since the gap checks stop within an iteration of
   *  it: 0.09% less again than 1e-2 (every cloud within -1.8% and +1.2%), 15% fewer
   *  iterations on a 1,000,000-point sphere (docs/evaluation.md). */
  static constexpr double kFittedTolerance = 2e-2;

  GraphTVSmoothing ()
  : GraphSmoothing<PointT> (core::TotalVariationParams{}.tolerance, kFittedTolerance,
                            core::TotalVariationParams{}.max_iterations)
  {
    filter_name_ = "GraphTVSmoothing";
  }

  /** \brief core::TotalVariationNorm::ISOTROPIC (default) or ANISOTROPIC. */
  inline void
  setNorm (core::TotalVariationNorm norm) { norm_ = norm; }

  /** \brief The norm set. */
  inline core::TotalVariationNorm
  getNorm () const { return norm_; }

protected:
  typename GraphSmoothing<PointT>::Smoother
  smoother (const core::PointGraph &graph, double gamma) const override;

  core::SmoothingKind
  smoothingKind () const override;

  double
  automaticGamma (const core::PointGraph &graph, double noise) const override;

private:
  core::TotalVariationNorm norm_ = core::TotalVariationNorm::ISOTROPIC;
};

} // namespace pcl_graph_denoise

#ifdef PCL_NO_PRECOMPILE
#include <pcl_graph_denoise/impl/graph_tv_smoothing.hpp>
#endif

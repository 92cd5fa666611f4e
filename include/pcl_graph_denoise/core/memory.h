/*
 * pcl_graph_denoise: graph-signal-processing point cloud denoising for PCL.
 * SPDX-License-Identifier: BSD-3-Clause
 */
#pragma once

/** \file memory.h
 *  \brief How much memory the filters' work needs, estimated before anything is
 *  allocated, so that a cloud too large for the memory allowed fails up front with a
 *  clear error instead of being killed half-way.
 *
 *  The estimates are upper bounds of the peak heap use measured by `bench/bench_memory`
 *  (docs/reliability.md gives the figures), in bytes, for n finite points; they count
 *  what the core allocates, not the caller's clouds. They saturate at SIZE_MAX. */

#include <cstddef>
#include <string>

namespace pcl_graph_denoise {
namespace core {

/** \brief The smoothing computations whose memory differs. */
enum class SmoothingKind
{
  TIKHONOV,          ///< conjugate gradient
  TIKHONOV_CHOLMOD,  ///< sparse Cholesky factorisation (its fill-in is bounded roughly)
  TOTAL_VARIATION    ///< primal-dual, with one dual value per edge and coordinate
};

/** \brief Physical memory of this machine in bytes (0 when it cannot be read). */
std::size_t
physicalMemory ();

/** \brief Peak bytes of buildKnnGraph on n points with k neighbours (k is capped at
 *  n - 1, as the graph does), the graph it returns included. */
std::size_t
knnGraphMemory (std::size_t n, std::size_t k);

/** \brief Peak bytes of one smoothing pass (graph, solver, noise estimate, normals and
 *  the displacement onto the local surface) on n points with k neighbours. */
std::size_t
smoothingMemory (std::size_t n, std::size_t k, SmoothingKind kind);

/** \brief Peak bytes of radiusGraphDegrees on n points (the degrees without the edges). */
std::size_t
radiusDegreesMemory (std::size_t n);

/** \brief Throws std::invalid_argument, naming `what`, both figures and the way out,
 *  when `needed` bytes exceed `limit`; a limit of 0 stands for physicalMemory () (and
 *  nothing is checked when that is unknown too). The way out names fewer points, the
 *  limit and `lever`, the caller's parameter that the memory grows with (default "k";
 *  empty when there is none). */
void
requireMemory (std::size_t needed, std::size_t limit, const std::string &what,
               const std::string &lever = "k");

} // namespace core
} // namespace pcl_graph_denoise

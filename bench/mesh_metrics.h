/*
 * pcl_graph_denoise: graph-signal-processing point cloud denoising for PCL.
 * SPDX-License-Identifier: BSD-3-Clause
 */
#pragma once

/* Triangle meshes as ground truth for the evaluation: loading, uniform sampling, the
 * unit-sphere normalisation of the score-based denoising protocol (Luo & Hu 2021), and
 * the distances it reports (Chamfer and point-to-mesh), built on CGAL's AABB tree. */

#include <pcl/point_cloud.h>
#include <pcl/point_types.h>

#include <Eigen/Core>

#include <array>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

namespace pcl_graph_denoise {
namespace evaluation {

using Cloud = pcl::PointCloud<pcl::PointXYZ>;

struct TriangleMesh
{
  std::vector<Eigen::Vector3d> vertices;
  std::vector<std::array<std::uint32_t, 3>> faces;
};

/** Reads an OFF, OBJ, PLY or STL file (polygons are split into triangle fans). Returns
 *  false with a message in `error` when the file cannot be read or has no triangle. */
bool
loadMesh (const std::string &path, TriangleMesh &mesh, std::string &error);

/** The surface's area: the sum of its triangles'. */
double
surfaceArea (const TriangleMesh &mesh);

/** n points uniform on the surface (triangles picked by area, then uniform barycentric
 *  coordinates), seeded. */
Cloud
sampleSurface (const TriangleMesh &mesh, std::size_t n, std::uint64_t seed);

/** p -> (p - centre) * scale. */
struct Similarity
{
  Eigen::Vector3d centre = Eigen::Vector3d::Zero ();
  double scale = 1.0;
};

/** The protocol's normalisation: the centre of the bounding box to the origin, then the
 *  largest distance to it scaled to 1. */
Similarity
unitSphereNormalisation (const Cloud &cloud);
/** The same, from the mesh's vertices. */
Similarity
unitSphereNormalisation (const TriangleMesh &mesh);

void
transform (const Similarity &s, Cloud &cloud);
void
transform (const Similarity &s, TriangleMesh &mesh);

/** Adds isotropic Gaussian noise of standard deviation sigma, seeded. */
Cloud
addGaussianNoise (const Cloud &cloud, double sigma, std::uint64_t seed);

/** Distances from points to a fixed triangle mesh. */
class MeshDistance
{
public:
  explicit MeshDistance (const TriangleMesh &mesh);
  ~MeshDistance ();
  MeshDistance (const MeshDistance &) = delete;
  MeshDistance &
  operator= (const MeshDistance &) = delete;

  double
  squaredDistance (const Eigen::Vector3d &p) const;

  const TriangleMesh &
  mesh () const
  {
    return mesh_;
  }

private:
  struct Tree;
  TriangleMesh mesh_;
  std::unique_ptr<Tree> tree_;
};

/** Chamfer distance as the protocol computes it: the mean squared distance from each
 *  point of a to its nearest point of b, plus the same from b to a. */
double
chamferDistance (const Cloud &a, const Cloud &b);

/** Point-to-mesh distance as the protocol computes it: the mean over the points of the
 *  squared distance to the nearest triangle, plus the mean over the triangles of the
 *  squared distance to the nearest point. */
double
pointToMeshDistance (const Cloud &cloud, const MeshDistance &mesh);

/** Mean (unsquared) distance of the points to the mesh. */
double
meanDistanceToMesh (const Cloud &cloud, const MeshDistance &mesh);

/** Distance of every point to the mesh. */
std::vector<double>
distancesToMesh (const Cloud &cloud, const MeshDistance &mesh);

/** Writes the cloud as a binary PCD with x y z and, as intensity, each point's distance
 *  to the mesh times `scale` (e.g. 1000 for millimetres from metres), for pictures. */
void
saveWithDistance (const std::string &path, const Cloud &cloud, const MeshDistance &mesh, double scale);

} // namespace evaluation
} // namespace pcl_graph_denoise

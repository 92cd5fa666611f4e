/*
 * pcl_graph_denoise: graph-signal-processing point cloud denoising for PCL.
 * SPDX-License-Identifier: BSD-3-Clause
 */
#include "mesh_metrics.h"

#include <pcl/io/pcd_io.h>
#include <pcl/kdtree/kdtree_flann.h>

#include <CGAL/AABB_traits.h>
#include <CGAL/AABB_tree.h>
#include <CGAL/AABB_triangle_primitive.h>
#include <CGAL/IO/polygon_soup_io.h>
#include <CGAL/Simple_cartesian.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>

namespace pcl_graph_denoise {
namespace evaluation {

namespace {

using Kernel = CGAL::Simple_cartesian<double>;
using Point3 = Kernel::Point_3;
using Triangle3 = Kernel::Triangle_3;

Point3
toCgal (const Eigen::Vector3d &p)
{
  return {p.x (), p.y (), p.z ()};
}

Triangle3
triangle (const TriangleMesh &mesh, const std::array<std::uint32_t, 3> &f)
{
  return {toCgal (mesh.vertices[f[0]]), toCgal (mesh.vertices[f[1]]), toCgal (mesh.vertices[f[2]])};
}

double
area (const TriangleMesh &mesh, const std::array<std::uint32_t, 3> &f)
{
  const Eigen::Vector3d &a = mesh.vertices[f[0]];
  return 0.5 * (mesh.vertices[f[1]] - a).cross (mesh.vertices[f[2]] - a).norm ();
}

} // namespace

bool
loadMesh (const std::string &path, TriangleMesh &mesh, std::string &error)
{
  std::vector<Point3> points;
  std::vector<std::vector<std::size_t>> polygons;
  if (!CGAL::IO::read_polygon_soup (path, points, polygons, CGAL::parameters::verbose (false)))
  {
    error = "cannot read a mesh from " + path;
    return false;
  }
  mesh = TriangleMesh ();
  for (const auto &p : points)
    mesh.vertices.emplace_back (p.x (), p.y (), p.z ());
  for (const auto &polygon : polygons)
    for (std::size_t i = 2; i < polygon.size (); ++i)
    {
      const std::array<std::size_t, 3> f = {polygon[0], polygon[i - 1], polygon[i]};
      if (std::any_of (f.begin (), f.end (), [&] (std::size_t v) { return v >= points.size (); }))
      {
        error = path + ": a face names a vertex that does not exist";
        return false;
      }
      mesh.faces.push_back ({std::uint32_t (f[0]), std::uint32_t (f[1]), std::uint32_t (f[2])});
    }
  if (mesh.faces.empty ())
  {
    error = path + " has no triangle";
    return false;
  }
  return true;
}

double
surfaceArea (const TriangleMesh &mesh)
{
  double total = 0.0;
  for (const auto &face : mesh.faces)
    total += area (mesh, face);
  return total;
}

Cloud
sampleSurface (const TriangleMesh &mesh, std::size_t n, std::uint64_t seed)
{
  std::vector<double> cumulative (mesh.faces.size ());
  double total = 0.0;
  for (std::size_t f = 0; f < mesh.faces.size (); ++f)
    cumulative[f] = total += area (mesh, mesh.faces[f]);
  std::mt19937_64 rng (seed);
  std::uniform_real_distribution<double> uniform (0.0, 1.0);
  Cloud cloud;
  cloud.reserve (n);
  for (std::size_t i = 0; i < n; ++i)
  {
    const std::size_t f = std::min<std::size_t> (
        std::upper_bound (cumulative.begin (), cumulative.end (), uniform (rng) * total) -
            cumulative.begin (),
        mesh.faces.size () - 1);
    const auto &face = mesh.faces[f];
    const double s = std::sqrt (uniform (rng)), t = uniform (rng);
    const Eigen::Vector3d p = (1.0 - s) * mesh.vertices[face[0]] +
                              s * (1.0 - t) * mesh.vertices[face[1]] + s * t * mesh.vertices[face[2]];
    cloud.push_back (pcl::PointXYZ (float (p.x ()), float (p.y ()), float (p.z ())));
  }
  return cloud;
}

namespace {

Similarity
boundingBoxCentreAndRadius (const std::vector<Eigen::Vector3d> &points)
{
  Eigen::Vector3d lo = Eigen::Vector3d::Constant (std::numeric_limits<double>::max ());
  Eigen::Vector3d hi = -lo;
  for (const auto &p : points)
  {
    lo = lo.cwiseMin (p);
    hi = hi.cwiseMax (p);
  }
  Similarity s;
  s.centre = 0.5 * (lo + hi);
  double radius = 0.0;
  for (const auto &p : points)
    radius = std::max (radius, (p - s.centre).norm ());
  s.scale = radius > 0.0 ? 1.0 / radius : 1.0;
  return s;
}

} // namespace

Similarity
unitSphereNormalisation (const Cloud &cloud)
{
  std::vector<Eigen::Vector3d> points;
  points.reserve (cloud.size ());
  for (const auto &p : cloud)
    points.push_back (p.getVector3fMap ().cast<double> ());
  return boundingBoxCentreAndRadius (points);
}

Similarity
unitSphereNormalisation (const TriangleMesh &mesh)
{
  return boundingBoxCentreAndRadius (mesh.vertices);
}

void
transform (const Similarity &s, Cloud &cloud)
{
  for (auto &p : cloud)
    p.getVector3fMap () = ((p.getVector3fMap ().cast<double> () - s.centre) * s.scale).cast<float> ();
}

void
transform (const Similarity &s, TriangleMesh &mesh)
{
  for (auto &v : mesh.vertices)
    v = (v - s.centre) * s.scale;
}

Cloud
addGaussianNoise (const Cloud &cloud, double sigma, std::uint64_t seed)
{
  std::mt19937_64 rng (seed);
  std::normal_distribution<double> normal (0.0, sigma);
  Cloud noisy = cloud;
  for (auto &p : noisy)
    for (int c = 0; c < 3; ++c)
      p.data[c] = float (p.data[c] + normal (rng));
  return noisy;
}

struct MeshDistance::Tree
{
  using Triangles = std::vector<Triangle3>;
  using Primitive = CGAL::AABB_triangle_primitive<Kernel, Triangles::const_iterator>;
  using Aabb = CGAL::AABB_tree<CGAL::AABB_traits<Kernel, Primitive>>;
  Triangles triangles;
  Aabb tree;
};

MeshDistance::MeshDistance (const TriangleMesh &mesh) : mesh_ (mesh), tree_ (new Tree)
{
  for (const auto &f : mesh_.faces)
    if (area (mesh_, f) > 0.0)  // degenerate triangles hold no surface
      tree_->triangles.push_back (triangle (mesh_, f));
  tree_->tree.insert (tree_->triangles.cbegin (), tree_->triangles.cend ());
  tree_->tree.build ();
  tree_->tree.accelerate_distance_queries ();
}

MeshDistance::~MeshDistance () = default;

double
MeshDistance::squaredDistance (const Eigen::Vector3d &p) const
{
  return tree_->tree.squared_distance (toCgal (p));
}

namespace {

/** Mean squared distance from each point of `from` to its nearest point of `to`. */
double
meanSquaredNearest (const Cloud &from, const Cloud &to)
{
  pcl::KdTreeFLANN<pcl::PointXYZ> tree;
  tree.setInputCloud (to.makeShared ());
  pcl::Indices index (1);
  std::vector<float> d2 (1);
  double sum = 0.0;
  for (const auto &p : from)
  {
    tree.nearestKSearch (p, 1, index, d2);
    sum += (p.getVector3fMap ().cast<double> () - to[index[0]].getVector3fMap ().cast<double> ())
               .squaredNorm ();
  }
  return sum / double (from.size ());
}

} // namespace

double
chamferDistance (const Cloud &a, const Cloud &b)
{
  return meanSquaredNearest (a, b) + meanSquaredNearest (b, a);
}

double
pointToMeshDistance (const Cloud &cloud, const MeshDistance &mesh)
{
  double points_to_mesh = 0.0;
  for (const auto &p : cloud)
    points_to_mesh += mesh.squaredDistance (p.getVector3fMap ().cast<double> ());
  points_to_mesh /= double (cloud.size ());

  // Each triangle's nearest point: the point nearest to the centroid c bounds it by U;
  // any point closer than U to the triangle lies within U + R of c (R: the largest
  // distance from c to a vertex), so that ball holds the answer.
  pcl::KdTreeFLANN<pcl::PointXYZ> tree;
  tree.setInputCloud (cloud.makeShared ());
  pcl::Indices index;
  std::vector<float> d2;
  double mesh_to_points = 0.0;
  std::size_t faces = 0;
  const TriangleMesh &m = mesh.mesh ();
  for (const auto &f : m.faces)
  {
    if (area (m, f) <= 0.0)
      continue;
    const Triangle3 t = triangle (m, f);
    const Eigen::Vector3d c = (m.vertices[f[0]] + m.vertices[f[1]] + m.vertices[f[2]]) / 3.0;
    double r = 0.0;
    for (int v = 0; v < 3; ++v)
      r = std::max (r, (m.vertices[f[v]] - c).norm ());
    const pcl::PointXYZ query (float (c.x ()), float (c.y ()), float (c.z ()));
    tree.nearestKSearch (query, 1, index, d2);
    const auto &q = cloud[index[0]];
    double best = CGAL::squared_distance (Point3 (q.x, q.y, q.z), t);
    tree.radiusSearch (query, std::sqrt (best) + r + 1e-6, index, d2);
    for (const auto i : index)
      best = std::min (best, CGAL::squared_distance (Point3 (cloud[i].x, cloud[i].y, cloud[i].z), t));
    mesh_to_points += best;
    ++faces;
  }
  return points_to_mesh + mesh_to_points / double (std::max<std::size_t> (faces, 1));
}

std::vector<double>
distancesToMesh (const Cloud &cloud, const MeshDistance &mesh)
{
  std::vector<double> d (cloud.size ());
  for (std::size_t i = 0; i < cloud.size (); ++i)
    d[i] = std::sqrt (mesh.squaredDistance (cloud[i].getVector3fMap ().cast<double> ()));
  return d;
}

void
saveWithDistance (const std::string &path, const Cloud &cloud, const MeshDistance &mesh, double scale)
{
  const std::vector<double> d = distancesToMesh (cloud, mesh);
  pcl::PointCloud<pcl::PointXYZI> out;
  for (std::size_t i = 0; i < cloud.size (); ++i)
  {
    pcl::PointXYZI p;
    p.getVector3fMap () = cloud[i].getVector3fMap ();
    p.intensity = float (d[i] * scale);
    out.push_back (p);
  }
  pcl::io::savePCDFileBinary (path, out);
}

double
meanDistanceToMesh (const Cloud &cloud, const MeshDistance &mesh)
{
  double sum = 0.0;
  for (double d : distancesToMesh (cloud, mesh))
    sum += d;
  return sum / double (std::max<std::size_t> (cloud.size (), 1));
}

} // namespace evaluation
} // namespace pcl_graph_denoise

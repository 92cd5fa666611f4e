/*
 * pcl_graph_denoise: graph-signal-processing point cloud denoising for PCL.
 * SPDX-License-Identifier: BSD-3-Clause
 *
 * Real scanner noise with a known surface: the raw Stanford bunny range scans (bun000,
 * bun045, bun090; Cyberware 3030MS) registered onto the Stanford reconstruction
 * bun_zipper.ply with Stanford's own registration (bun.conf: a scan point p maps to
 * R^T p + t, R the rotation of the quaternion). The mean distance of the points to the
 * reconstruction, in millimetres, before and after every method; "best" settings are
 * chosen by that distance. The residual includes the registration error, which no
 * denoiser can remove. Writes bunny.md, and bunny_<scan>_<method>.pcd (x y z and the
 * distance in mm as intensity) for the pictures. Quick mode: bun000 only.
 */
#include "evaluate.h"

#include "mesh_metrics.h"

#include <pcl/common/io.h>
#include <pcl/common/point_tests.h>
#include <pcl/io/pcd_io.h>
#include <pcl/io/ply_io.h>

#include <Eigen/Geometry>

#include <cmath>
#include <fstream>
#include <map>
#include <sstream>

namespace pcl_graph_denoise {
namespace evaluation {

namespace {

/** Stanford's registration of each scan, from bun.conf. */
std::map<std::string, Eigen::Isometry3d>
readRegistration (const std::string &path)
{
  std::map<std::string, Eigen::Isometry3d> poses;
  std::ifstream in (path);
  std::string line;
  while (std::getline (in, line))
  {
    std::istringstream fields (line);
    std::string kind, file;
    double t[3], q[4];
    if (fields >> kind >> file >> t[0] >> t[1] >> t[2] >> q[0] >> q[1] >> q[2] >> q[3] && kind == "bmesh")
    {
      const Eigen::Quaterniond rotation (q[3], q[0], q[1], q[2]);
      Eigen::Isometry3d pose = Eigen::Isometry3d::Identity ();
      pose.linear () = rotation.normalized ().toRotationMatrix ().transpose ();
      pose.translation () = Eigen::Vector3d (t[0], t[1], t[2]);
      poses[file] = pose;
    }
  }
  return poses;
}

} // namespace

int
bunny (const Options &options)
{
  const std::string scans = options.data + "/real/stanford_bunny_scans";
  TriangleMesh mesh;
  std::string error;
  if (!loadMesh (options.data + "/meshes/stanford/bun_zipper.ply", mesh, error))
  {
    std::fprintf (stderr, "error: %s\n", error.c_str ());
    return 2;
  }
  const MeshDistance distance (mesh);
  const auto poses = readRegistration (scans + "/bun.conf");
  const std::vector<std::string> files =
      options.quick ? std::vector<std::string>{"bun000.ply"}
                    : std::vector<std::string>{"bun000.ply", "bun045.ply", "bun090.ply"};
  MethodOptions method_options = methodOptions (options);
  method_options.wlop = false;  // about 2 minutes per scan here

  std::map<std::string, std::vector<MethodResult>> table;
  for (const auto &file : files)
  {
    pcl::PointCloud<pcl::PointXYZ> raw;
    if (poses.count (file) == 0 || pcl::io::loadPLYFile (scans + "/" + file, raw) < 0)
    {
      std::fprintf (stderr, "error: cannot read %s or its registration in %s/bun.conf\n", file.c_str (),
                    scans.c_str ());
      return 2;
    }
    // The samples the scanner missed are NaN (PCL's PLY reader marks the cloud dense
    // all the same, so removeNaNFromPointCloud would keep them).
    const Cloud::Ptr scan (new Cloud);
    const Eigen::Isometry3f pose = poses.at (file).cast<float> ();
    for (const auto &p : raw)
      if (pcl::isFinite (p))
        scan->push_back (pcl::PointXYZ (0, 0, 0)), scan->back ().getVector3fMap () = pose * p.getVector3fMap ();
    auto results = runMethods (
        scan, [&] (const Cloud &out) { return meanDistanceToMesh (out, distance) * 1000.0; },
        method_options);
    const std::string stem = file.substr (0, file.size () - 4);
    std::printf ("%s (%zu points): mean distance to bun_zipper in mm:", stem.c_str (), scan->size ());
    for (const auto &r : results)
      std::printf ("  %s %.4f", r.method.c_str (), r.error);
    std::printf ("\n");
    for (const auto &r : results)
      if (r.method == "noisy input" || r.method == "TV (defaults)" || r.method == "Tikhonov (defaults)" ||
          r.method == "MLS (best radius)" || r.method == "jet (best k)")
      {
        std::string name = r.method.substr (0, r.method.find (' '));
        saveWithDistance (options.out + "/bunny_" + stem + "_" + name + ".pcd", r.output, distance, 1000.0);
      }
    table[stem] = std::move (results);
  }

  std::ofstream md (options.out + "/bunny.md");
  md << runNote (options);
  md << "| method |";
  for (const auto &scan : table)
    md << ' ' << scan.first << " (" << scan.second.front ().output.size () << " points) |";
  md << "\n|---|";
  for (std::size_t i = 0; i < table.size (); ++i)
    md << "---|";
  md << '\n';
  char cell[96];
  const auto &methods = methodNames ();
  for (std::size_t m = 0; m < methods.size (); ++m)
  {
    if (std::isnan (table.begin ()->second[m].error))
      continue;
    md << "| " << methods[m] << " |";
    for (const auto &scan : table)
    {
      const auto &r = scan.second[m];
      std::snprintf (cell, sizeof (cell), " %.4f mm (%.2f s%s%s) |", r.error, r.seconds,
                     r.setting.empty () ? "" : ", ", r.setting.c_str ());
      md << cell;
    }
    md << '\n';
  }
  std::vector<Finding> findings;
  for (const char *ours : {"TV (defaults)", "Tikhonov (defaults)"})
  {
    int wins = 0, reduces = 0;
    for (const auto &scan : table)
    {
      const auto &r = scan.second;
      const std::size_t i = std::find (methods.begin (), methods.end (), ours) - methods.begin ();
      bool best = true;
      for (std::size_t p = firstPeer (); p < methods.size (); ++p)
        best = best && !(r[i].error >= r[p].error);
      wins += best;
      reduces += r[i].error < r[0].error;
    }
    std::ostringstream text;
    text << ours << " lowers the distance to the reconstruction on " << reduces << " of " << table.size ()
         << " scans, and below every peer's best on " << wins;
    findings.push_back ({text.str (), reduces == int (table.size ()), true});
  }
  md << "\nFindings on these numbers:\n\n";
  const int failed = reportFindings (findings, md);
  return options.quick && failed > 0 ? 1 : 0;
}

} // namespace evaluation
} // namespace pcl_graph_denoise

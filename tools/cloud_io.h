/*
 * pcl_graph_denoise: graph-signal-processing point cloud denoising for PCL.
 * SPDX-License-Identifier: BSD-3-Clause
 */
#pragma once

#include <pcl/PCLPointCloud2.h>

#include <Eigen/Geometry>

#include <stdexcept>
#include <string>
#include <vector>

namespace pcl_graph_denoise {
namespace tools {

/** \brief A failure of the tool, reported as one line on stderr. */
struct Error : std::runtime_error
{
  using std::runtime_error::runtime_error;
};

/** \brief The file formats the tool reads and writes. */
enum class FileFormat
{
  PCD,
  PLY
};

/** \brief The format named by the extension of a path (.pcd or .ply, any case).
 *  \throws Error for another extension. */
FileFormat
formatOf (const std::string &path);

/** \brief A cloud with every field of its file, and the sensor pose stored with it. */
struct CloudFile
{
  pcl::PCLPointCloud2 cloud;
  Eigen::Vector4f origin = Eigen::Vector4f::Zero ();
  Eigen::Quaternionf orientation = Eigen::Quaternionf::Identity ();
};

/** \brief Reads a .pcd or .ply file with all its fields.
 *
 * PCL 1.13's readers crash on some malformed files and allocate what a header
 * announces before finding out that the file is shorter, so the header is checked
 * first: the structure, the field types and sizes, and that the file is long enough for
 * the points it announces. The result's layout is checked again after reading.
 *  \throws Error (one line, naming the file) if the file is missing, malformed,
 *  truncated or holds no point. */
CloudFile
loadCloud (const std::string &path);

/** \brief Files written under a temporary name beside their destination and renamed
 *  into place together by commit(); whatever is not committed is removed on
 *  destruction, so that a failure leaves no partial output behind. */
class PendingFiles
{
public:
  PendingFiles () = default;
  ~PendingFiles ();
  PendingFiles (const PendingFiles &) = delete;
  PendingFiles &
  operator= (const PendingFiles &) = delete;

  /** \brief Fails early when path cannot be written (missing folder, no
   *  permission), before any work is done; creates and removes a temporary file.
   *  \throws Error */
  static void
  checkWritable (const std::string &path);

  /** \brief Writes a cloud to a temporary file beside path, in the format of path's
   *  extension, binary or ASCII.
   *  \throws Error */
  void
  write (const std::string &path, const CloudFile &file, bool binary);

  /** \brief Renames every written file to its destination.
   *  \throws Error */
  void
  commit ();

private:
  struct Pending
  {
    std::string temporary, destination;
  };
  std::vector<Pending> pending_;
};

}  // namespace tools
}  // namespace pcl_graph_denoise

/*
 * pcl_graph_denoise: graph-signal-processing point cloud denoising for PCL.
 * SPDX-License-Identifier: BSD-3-Clause
 */
#include "cloud_io.h"

#include "stderr_capture.h"

#include <pcl/common/io.h>
#include <pcl/io/pcd_io.h>
#include <pcl/io/ply_io.h>

#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <sstream>
#include <system_error>

namespace pcl_graph_denoise {
namespace tools {

namespace {

namespace fs = std::filesystem;

/** Headers longer than this are not headers. */
constexpr std::size_t max_header_bytes = 1 << 20;

std::string
lowerExtension (const std::string &path)
{
  std::string ext = fs::path (path).extension ().string ();
  std::transform (ext.begin (), ext.end (), ext.begin (),
                  [] (unsigned char c) { return static_cast<char> (std::tolower (c)); });
  return ext;
}

std::vector<std::string>
split (const std::string &line)
{
  std::istringstream in (line);
  std::vector<std::string> tokens;
  std::string token;
  while (in >> token)
    tokens.push_back (token);
  return tokens;
}

/** A whole token as an unsigned integer (digits only). */
bool
parseCount (const std::string &token, std::uint64_t &value)
{
  if (token.empty () || token.size () > 19 ||
      !std::all_of (token.begin (), token.end (),
                    [] (unsigned char c) { return std::isdigit (c); }))
    return false;
  value = std::stoull (token);
  return true;
}

/** Reads the header lines of a text-headed file (PCD, PLY) up to and including the
 *  line whose first token is `last`; `data_offset` receives the byte after it. */
std::vector<std::vector<std::string>>
readHeaderLines (const std::string &path, const char *format, const char *last,
                 std::uint64_t &data_offset)
{
  std::ifstream in (path, std::ios::binary);
  if (!in)
    throw Error (path + ": cannot open it: " + std::strerror (errno));
  std::vector<std::vector<std::string>> lines;
  std::string line;
  data_offset = 0;
  while (std::getline (in, line))
  {
    data_offset += line.size () + 1;
    if (data_offset > max_header_bytes)
      break;
    if (!line.empty () && line.back () == '\r')
      line.pop_back ();
    lines.push_back (split (line));
    if (!lines.back ().empty () && lines.back ()[0] == last)
      return lines;
  }
  throw Error (path + ": not a " + format + " file (no complete header: no '" + last + "' line)");
}

std::string
pointsText (std::uint64_t n)
{
  return std::to_string (n) + (n == 1 ? " point" : " points");
}

/** PCL's PCD header parser does not stop at the DATA line: it goes on taking lines for
 *  header lines (keywords matched as prefixes, comments and empty lines skipped) until one
 *  is not. Data that begins like a header line (an ASCII line "COLUMNS0.5 ...", binary
 *  bytes "POINTS 999999999") then redefines the fields or the size of a cloud already
 *  sized, and PCL 1.13's reader crashes (SIGSEGV; found by fuzz/fuzz_cloud_file).
 *  Returns the first token of the first such line, or an empty string. */
std::string
headerLikeDataLine (const std::string &path, std::uint64_t data_offset)
{
  static const char *const keywords[] = {"VERSION", "FIELDS", "COLUMNS",   "SIZE",
                                         "TYPE",    "COUNT",  "WIDTH",     "HEIGHT",
                                         "VIEWPOINT", "POINTS", "DATA"};
  std::ifstream in (path, std::ios::binary);
  in.seekg (static_cast<std::streamoff> (data_offset));
  std::string line;
  while (std::getline (in, line))
  {
    if (line.empty ())
      continue;
    const std::vector<std::string> tokens = split (line);
    if (tokens.empty ())
      return {};  // PCL stops here
    const std::string &first = tokens[0];
    if (first[0] == '#')
      continue;  // a comment to PCL, which reads on
    for (const char *keyword : keywords)
      if (first.compare (0, std::strlen (keyword), keyword) == 0)
        return first;
    return {};
  }
  return {};
}

/** Checks a PCD header and that the file holds the data it announces. */
void
checkPcdFile (const std::string &path, std::uint64_t file_size)
{
  std::uint64_t offset = 0;
  const auto lines = readHeaderLines (path, "PCD", "DATA", offset);
  const auto bad = [&] (const std::string &why) {
    return Error (path + ": not a valid PCD file (" + why + ")");
  };
  std::vector<std::string> names, sizes, types, counts;
  std::uint64_t width = 0, height = 1, points = 0;
  bool has_width = false, has_points = false;
  std::string data;
  for (const auto &tokens : lines)
  {
    if (tokens.empty () || tokens[0][0] == '#')
      continue;
    const std::string &key = tokens[0];
    const std::vector<std::string> values (tokens.begin () + 1, tokens.end ());
    const auto single = [&] (std::uint64_t &value) {
      if (values.size () != 1 || !parseCount (values[0], value))
        throw bad ("invalid " + key + " line");
    };
    if (key == "VERSION" || key == "VIEWPOINT")
      continue;
    if (key == "FIELDS" || key == "COLUMNS")
      names = values;
    else if (key == "SIZE")
      sizes = values;
    else if (key == "TYPE")
      types = values;
    else if (key == "COUNT")
      counts = values;
    else if (key == "WIDTH")
    {
      single (width);
      has_width = true;
    }
    else if (key == "HEIGHT")
      single (height);
    else if (key == "POINTS")
    {
      single (points);
      has_points = true;
    }
    else if (key == "DATA")
      data = values.empty () ? std::string () : values[0];
    else
      throw bad ("unexpected header line '" + printable (key, 40) + "'");
  }
  if (names.empty ())
    throw bad ("no FIELDS in its header");
  if (sizes.size () != names.size () || types.size () != names.size () ||
      (!counts.empty () && counts.size () != names.size ()))
    throw bad ("FIELDS, SIZE, TYPE and COUNT do not have the same number of entries");
  std::uint64_t point_step = 0, values_per_point = 0;
  for (std::size_t i = 0; i < names.size (); ++i)
  {
    std::uint64_t size = 0, count = 1;
    if (!parseCount (sizes[i], size) || (!counts.empty () && !parseCount (counts[i], count)))
      throw bad ("invalid SIZE or COUNT of field '" + printable (names[i], 40) + "'");
    const bool integer = types[i] == "I" || types[i] == "U";
    if (!((integer && (size == 1 || size == 2 || size == 4 || size == 8)) ||
          (types[i] == "F" && (size == 4 || size == 8))))
      throw bad ("field '" + printable (names[i], 40) + "' has TYPE " + printable (types[i], 8) +
                 " and SIZE " + printable (sizes[i], 8));
    if (count < 1 || count > (1u << 20))
      throw bad ("field '" + printable (names[i], 40) + "' has COUNT " + printable (counts[i], 20));
    point_step += size * count;
    values_per_point += count;
  }
  if (!has_width && !has_points)
    throw bad ("neither WIDTH nor POINTS in its header");
  if (!has_width)
    width = points;
  if (height != 0 && width > std::numeric_limits<std::uint32_t>::max () / height)
    throw bad ("WIDTH x HEIGHT is too large");
  if (!has_points)
    points = width * height;
  if (points != width * height)
    throw bad ("WIDTH " + std::to_string (width) + " x HEIGHT " + std::to_string (height) +
               " differs from POINTS " + std::to_string (points));
  if (data != "ascii" && data != "binary" && data != "binary_compressed")
    throw bad ("DATA '" + printable (data, 40) + "': expected ascii, binary or binary_compressed");
  if (points == 0)
    throw Error (path + ": the cloud is empty (0 points)");
  const std::string header_like = headerLikeDataLine (path, offset);
  if (!header_like.empty ())
    throw bad ("its data begins with a line that PCL reads as a header line ('" +
               printable (header_like, 40) + "')");

  const std::uint64_t available = file_size > offset ? file_size - offset : 0;
  const auto truncated = [&] (const std::string &what) {
    return Error (path + ": truncated: its header announces " + pointsText (points) + " (" + what +
                  ") but only " + std::to_string (available) + " bytes follow it");
  };
  if (data == "binary")
  {
    if (points > available / point_step)
      throw truncated (std::to_string (points * point_step) + " bytes");
  }
  else if (data == "ascii")
  {
    // At least one character and one separator per value.
    if (points > (available + 1) / (2 * values_per_point))
      throw truncated ("at least " + std::to_string (2 * values_per_point * points - 1) +
                       " bytes as text");
  }
  else
  {
    // binary_compressed: the compressed and uncompressed sizes, then the compressed data.
    if (available < 8)
      throw truncated ("compressed");
    std::ifstream in (path, std::ios::binary);
    in.seekg (static_cast<std::streamoff> (offset));
    std::uint32_t sizes_read[2] = {0, 0};
    in.read (reinterpret_cast<char *> (sizes_read), sizeof (sizes_read));
    if (!in)
      throw truncated ("compressed");
    if (sizes_read[1] != points * point_step)
      throw bad ("binary_compressed data of " + std::to_string (sizes_read[1]) +
                 " bytes uncompressed, where the header announces " +
                 std::to_string (points * point_step));
    if (sizes_read[0] > available - 8)
      throw truncated (std::to_string (sizes_read[0]) + " compressed bytes");
  }
}

/** Size in bytes of a PLY scalar type, 0 if unknown. */
std::uint64_t
plyTypeSize (const std::string &type)
{
  if (type == "char" || type == "uchar" || type == "int8" || type == "uint8")
    return 1;
  if (type == "short" || type == "ushort" || type == "int16" || type == "uint16")
    return 2;
  if (type == "int" || type == "uint" || type == "int32" || type == "uint32" || type == "float" ||
      type == "float32")
    return 4;
  if (type == "double" || type == "float64")
    return 8;
  return 0;
}

/** Checks a PLY header and that the file is long enough for the elements it announces. */
void
checkPlyFile (const std::string &path, std::uint64_t file_size)
{
  {
    std::ifstream in (path, std::ios::binary);
    char magic[4] = {0, 0, 0, 0};
    in.read (magic, 4);
    if (!in || std::memcmp (magic, "ply", 3) != 0 || (magic[3] != '\n' && magic[3] != '\r'))
      throw Error (path + ": not a PLY file (it does not start with 'ply')");
  }
  std::uint64_t offset = 0;
  const auto lines = readHeaderLines (path, "PLY", "end_header", offset);
  const auto bad = [&] (const std::string &why) {
    return Error (path + ": not a valid PLY file (" + why + ")");
  };
  std::string format;
  struct Element
  {
    std::uint64_t count = 0, min_binary_bytes = 0, values = 0;
  };
  std::vector<Element> elements;
  std::uint64_t vertices = 0;
  bool has_vertex = false;
  for (std::size_t i = 1; i < lines.size (); ++i)
  {
    const auto &tokens = lines[i];
    if (tokens.empty () || tokens[0] == "comment" || tokens[0] == "obj_info" ||
        tokens[0] == "end_header")
      continue;
    if (tokens[0] == "format")
    {
      if (tokens.size () != 3 || (tokens[1] != "ascii" && tokens[1] != "binary_little_endian" &&
                                  tokens[1] != "binary_big_endian"))
        throw bad ("unknown format line");
      format = tokens[1];
    }
    else if (tokens[0] == "element")
    {
      Element element;
      if (tokens.size () != 3 || !parseCount (tokens[2], element.count))
        throw bad ("invalid element line");
      if (tokens[1] == "vertex")
      {
        has_vertex = true;
        vertices = element.count;
      }
      elements.push_back (element);
    }
    else if (tokens[0] == "property")
    {
      if (elements.empty ())
        throw bad ("a property before any element");
      Element &element = elements.back ();
      if (tokens.size () == 3 && plyTypeSize (tokens[1]) > 0)
        element.min_binary_bytes += plyTypeSize (tokens[1]);
      else if (tokens.size () == 5 && tokens[1] == "list" && plyTypeSize (tokens[2]) > 0 &&
               plyTypeSize (tokens[3]) > 0)
        element.min_binary_bytes += plyTypeSize (tokens[2]);  // an empty list
      else
        throw bad ("invalid property line");
      ++element.values;
    }
    else
      throw bad ("unexpected header line '" + printable (tokens[0], 40) + "'");
  }
  if (format.empty ())
    throw bad ("no format line");
  if (!has_vertex)
    throw Error (path + ": no vertex element: no x, y, z");
  if (vertices == 0)
    throw Error (path + ": the cloud is empty (0 points)");

  const std::uint64_t available = file_size > offset ? file_size - offset : 0;
  // The least the elements need: binary, their fixed sizes; ASCII, one character and one
  // separator per value. Computed in long double: counts may be absurd.
  long double needed = 0.0L;
  for (const Element &element : elements)
    needed += static_cast<long double> (element.count) *
              (format == "ascii" ? 2.0L * element.values : element.min_binary_bytes);
  if (format == "ascii" && needed > 0.0L)
    needed -= 1.0L;
  if (needed > static_cast<long double> (available))
    throw Error (path + ": truncated: its header announces " + pointsText (vertices) +
                 " (at least " + std::to_string (static_cast<unsigned long long> (needed)) +
                 " bytes of data) but only " + std::to_string (available) + " bytes follow it");
}

/** Checks the layout of a cloud read by PCL: its fields lie within a point, its data
 *  holds every point. */
void
checkLayout (const std::string &path, const pcl::PCLPointCloud2 &cloud)
{
  const std::uint64_t width = cloud.width, height = cloud.height;
  if (cloud.fields.empty ())
    throw Error (path + ": no fields: no x, y, z");
  if (width * height == 0)
    throw Error (path + ": the cloud is empty (0 points)");
  for (const auto &field : cloud.fields)
  {
    const std::uint64_t size = pcl::getFieldSize (field.datatype);
    if (size == 0 || std::uint64_t (field.offset) + size * field.count > cloud.point_step)
      throw Error (path + ": field '" + printable (field.name, 40) +
                   "' does not fit in a point (unknown type or offset)");
  }
  if (cloud.point_step == 0 || cloud.row_step < width * cloud.point_step ||
      cloud.data.size () < (height - 1) * cloud.row_step + width * cloud.point_step)
    throw Error (path + ": inconsistent data layout (" + pointsText (width * height) + " of " +
                 std::to_string (cloud.point_step) + " bytes, " +
                 std::to_string (cloud.data.size ()) + " bytes of data)");
}

}  // namespace

FileFormat
formatOf (const std::string &path)
{
  const std::string ext = lowerExtension (path);
  if (ext == ".pcd")
    return FileFormat::PCD;
  if (ext == ".ply")
    return FileFormat::PLY;
  throw Error (path + ": unknown file type '" + printable (ext, 20) + "' (expected .pcd or .ply)");
}

CloudFile
loadCloud (const std::string &path)
{
  const FileFormat format = formatOf (path);
  std::error_code ec;
  if (!fs::exists (path, ec))
    throw Error (path + ": no such file");
  if (!fs::is_regular_file (path, ec))
    throw Error (path + ": not a regular file");
  const std::uint64_t file_size = fs::file_size (path, ec);
  if (ec)
    throw Error (path + ": cannot read it: " + ec.message ());
  if (file_size == 0)
    throw Error (path + ": empty file");
  if (format == FileFormat::PCD)
    checkPcdFile (path, file_size);
  else
    checkPlyFile (path, file_size);

  CloudFile file;
  int result = -1;
  std::string captured, failure;
  {
    StderrCapture capture;
    try
    {
      if (format == FileFormat::PCD)
      {
        pcl::PCDReader reader;
        int version = 0;
        result = reader.read (path, file.cloud, file.origin, file.orientation, version);
      }
      else
      {
        pcl::PLYReader reader;
        int version = 0;
        result = reader.read (path, file.cloud, file.origin, file.orientation, version);
      }
    }
    catch (const std::exception &e)
    {
      failure = e.what ();
      result = -1;
    }
    captured = capture.release ();
  }
  if (result < 0)
  {
    if (failure.empty ())
      failure = mainMessage (captured);
    throw Error (path + ": cannot read it as a " +
                 (format == FileFormat::PCD ? std::string ("PCD") : std::string ("PLY")) + " file" +
                 (failure.empty () ? std::string () : ": " + printable (failure)));
  }
  checkLayout (path, file.cloud);
  return file;
}

// --- Writing ----------------------------------------------------------------------------

namespace {

/** PCL's PLY writer refuses a cloud without points (e.g. the -removed file when no point
 *  was removed): a PLY file of no vertex, 0 on success. */
int
writeEmptyPly (const std::string &path, bool binary)
{
  std::ofstream out (path, std::ios::binary);
  out << "ply\nformat " << (binary ? "binary_little_endian" : "ascii") << " 1.0\n"
      << "comment PCL generated\nelement vertex 0\nproperty float x\nproperty float y\n"
      << "property float z\nend_header\n";
  out.close ();
  return out ? 0 : -1;
}

std::string
temporaryPath (const std::string &path)
{
  const fs::path p (path);
  return (p.parent_path () /
          ("." + p.filename ().string () + ".partial-" + std::to_string (::getpid ())))
      .string ();
}

}  // namespace

void
PendingFiles::checkWritable (const std::string &path)
{
  formatOf (path);
  std::error_code ec;
  if (fs::is_directory (path, ec))
    throw Error ("cannot write " + path + ": it is a folder");
  const std::string temporary = temporaryPath (path);
  std::FILE *f = std::fopen (temporary.c_str (), "wb");
  if (!f)
    throw Error ("cannot write " + path + ": " + std::strerror (errno));
  std::fclose (f);
  std::remove (temporary.c_str ());
}

void
PendingFiles::write (const std::string &path, const CloudFile &file, bool binary)
{
  const FileFormat format = formatOf (path);
  // Numbered: two outputs never share a temporary file.
  const std::string temporary = temporaryPath (path) + "-" + std::to_string (pending_.size ());
  pending_.push_back ({temporary, path});
  // Nine significant digits write a float exactly, seventeen a double.
  const bool doubles = std::any_of (
      file.cloud.fields.begin (), file.cloud.fields.end (),
      [] (const pcl::PCLPointField &f) { return f.datatype == pcl::PCLPointField::FLOAT64; });
  const int precision = doubles ? 17 : 9;
  int result = -1;
  std::string failure, captured;
  {
    StderrCapture capture;
    try
    {
      if (format == FileFormat::PCD)
      {
        pcl::PCDWriter writer;
        result = binary ? writer.writeBinary (temporary, file.cloud, file.origin, file.orientation)
                        : writer.writeASCII (temporary, file.cloud, file.origin, file.orientation,
                                             precision);
      }
      else if (std::size_t (file.cloud.width) * file.cloud.height == 0)
        result = writeEmptyPly (temporary, binary);
      else
      {
        pcl::PLYWriter writer;
        result = binary ? writer.writeBinary (temporary, file.cloud, file.origin, file.orientation)
                        : writer.writeASCII (temporary, file.cloud, file.origin, file.orientation,
                                             precision);
      }
    }
    catch (const std::exception &e)
    {
      failure = e.what ();
      result = -1;
    }
    captured = capture.release ();
  }
  std::error_code ec;
  if (result < 0 || !fs::is_regular_file (temporary, ec))
  {
    if (failure.empty ())
      failure = mainMessage (captured);
    throw Error ("cannot write " + path +
                 (failure.empty () ? std::string () : ": " + printable (failure)));
  }
}

void
PendingFiles::commit ()
{
  for (std::size_t i = 0; i < pending_.size (); ++i)
  {
    if (std::rename (pending_[i].temporary.c_str (), pending_[i].destination.c_str ()) != 0)
    {
      const std::string why = std::strerror (errno);
      // All or nothing: the outputs renamed already go too (the rest on destruction).
      for (std::size_t j = 0; j < i; ++j)
        std::remove (pending_[j].destination.c_str ());
      throw Error ("cannot write " + pending_[i].destination + ": " + why);
    }
    pending_[i].temporary.clear ();
  }
  pending_.clear ();
}

PendingFiles::~PendingFiles ()
{
  for (const auto &file : pending_)
    if (!file.temporary.empty ())
      std::remove (file.temporary.c_str ());
}

}  // namespace tools
}  // namespace pcl_graph_denoise

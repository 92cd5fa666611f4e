/*
 * pcl_graph_denoise: graph-signal-processing point cloud denoising for PCL.
 * SPDX-License-Identifier: BSD-3-Clause
 */
#include "stderr_capture.h"

#include <unistd.h>

#include <array>
#include <sstream>
#include <vector>

namespace pcl_graph_denoise {
namespace tools {

StderrCapture::StderrCapture ()
{
  std::fflush (stderr);
  file_ = std::tmpfile ();
  if (!file_)
    return;
  saved_fd_ = ::dup (STDERR_FILENO);
  if (saved_fd_ < 0 || ::dup2 (::fileno (file_), STDERR_FILENO) < 0)
  {
    if (saved_fd_ >= 0)
      ::close (saved_fd_);
    saved_fd_ = -1;
    std::fclose (file_);
    file_ = nullptr;
  }
}

StderrCapture::~StderrCapture ()
{
  release ();
}

void
StderrCapture::writeThrough (const std::string &text) const
{
  if (saved_fd_ < 0)
  {
    std::fputs (text.c_str (), stderr);
    std::fflush (stderr);
    return;
  }
  std::size_t done = 0;
  while (done < text.size ())
  {
    const ::ssize_t n = ::write (saved_fd_, text.data () + done, text.size () - done);
    if (n <= 0)
      return;
    done += static_cast<std::size_t> (n);
  }
}

std::string
StderrCapture::release ()
{
  if (!file_)
    return {};
  std::fflush (stderr);
  ::dup2 (saved_fd_, STDERR_FILENO);
  ::close (saved_fd_);
  saved_fd_ = -1;
  std::string text;
  std::rewind (file_);
  std::array<char, 4096> buffer;
  std::size_t n;
  while ((n = std::fread (buffer.data (), 1, buffer.size (), file_)) > 0)
    text.append (buffer.data (), n);
  std::fclose (file_);
  file_ = nullptr;
  return text;
}

std::string
printable (const std::string &text, std::size_t max_length)
{
  std::string out;
  for (const char c : text)
    out += (static_cast<unsigned char> (c) < 0x20 || c == 0x7f) ? '?' : c;
  if (out.size () > max_length)
    out = out.substr (0, max_length) + "...";
  return out;
}

std::string
mainMessage (const std::string &captured)
{
  static const std::array<const char *, 4> noise = {
      "is not handled", "ignoring", "problem parsing header", "no fitting callbacks"};
  std::istringstream lines (captured);
  std::string line, best;
  while (std::getline (lines, line))
  {
    // Drop terminal colour codes and the "[pcl::Class::method] " tag.
    std::string clean;
    for (std::size_t i = 0; i < line.size (); ++i)
    {
      if (line[i] == '\x1b')
      {
        while (i < line.size () && line[i] != 'm')
          ++i;
        continue;
      }
      if (line[i] != '\r')
        clean += line[i];
    }
    if (!clean.empty () && clean[0] == '[')
    {
      const auto end = clean.find ("] ");
      if (end != std::string::npos)
        clean = clean.substr (end + 2);
    }
    while (!clean.empty () &&
           (clean.back () == ' ' || clean.back () == '.' || clean.back () == '!'))
      clean.pop_back ();
    bool skip = clean.empty ();
    for (const char *n : noise)
      skip = skip || clean.find (n) != std::string::npos;
    // The last line that is not noise is the most specific one (PCL's readers print
    // the generic failure last, which is in the noise list).
    if (!skip)
      best = clean;
  }
  return printable (best);
}

}  // namespace tools
}  // namespace pcl_graph_denoise

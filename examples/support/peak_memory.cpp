/*
 * pcl_graph_denoise: graph-signal-processing point cloud denoising for PCL.
 * SPDX-License-Identifier: BSD-3-Clause
 */
#include "peak_memory.h"

#include "timing.h"

#include <sys/wait.h>
#include <unistd.h>

#include <cstdlib>
#include <fstream>
#include <string>

namespace pcl_graph_denoise {
namespace synthetic {

namespace {

/** A field of /proc/self/status in bytes (its values are in kB), or -1. */
long long
statusBytes (const std::string &field)
{
  std::ifstream status ("/proc/self/status");
  std::string line;
  while (std::getline (status, line))
    if (line.compare (0, field.size () + 1, field + ":") == 0)
      return std::atoll (line.c_str () + field.size () + 1) * 1024;
  return -1;
}

} // namespace

PeakMemory
measurePeakMemory (const std::function<std::size_t ()> &work)
{
  int fds[2];
  if (pipe (fds) != 0)
    return {};
  const pid_t pid = fork ();
  if (pid == 0)
  {
    close (fds[0]);
    PeakMemory m;
    bool reset = false;
    {
      std::ofstream clear ("/proc/self/clear_refs");
      reset = static_cast<bool> (clear << "5" << std::flush);
    }
    const long long start = statusBytes ("VmRSS");
    m.seconds = seconds ([&] { m.returned = work (); });
    const long long peak = statusBytes ("VmHWM");
    m.bytes = reset && start >= 0 && peak >= 0 ? double (peak - start) : -1.0;
    const ssize_t written = write (fds[1], &m, sizeof (m));
    _exit (written == ssize_t (sizeof (m)) ? 0 : 1);
  }
  close (fds[1]);
  PeakMemory m;
  const ssize_t got = pid > 0 ? read (fds[0], &m, sizeof (m)) : -1;
  close (fds[0]);
  int status = 0;
  if (pid > 0)
    waitpid (pid, &status, 0);
  return got == ssize_t (sizeof (m)) && WIFEXITED (status) && WEXITSTATUS (status) == 0 ? m
                                                                                    : PeakMemory{};
}

} // namespace synthetic
} // namespace pcl_graph_denoise

// Writing files that other programs read while they may be written: atomic replacement, and
// numbers as text that reads back bit for bit. Used by the map writer here and by every other
// package that writes result files (e.g. minibot3d_slam's trajectories and relations).
#ifndef MINIBOT3D_MAP_IO_FILE_UTIL_H_
#define MINIBOT3D_MAP_IO_FILE_UTIL_H_

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>

namespace minibot3d_map_io {

// Replaces `path` with `contents` through a temporary file in the same folder that is renamed
// into place: a reader (map_server, amcl, a script) never sees a half-written file, and a failed
// write leaves the previous file as it was. Returns "" on success, else why it failed (the caller
// names the file in its own error type).
inline std::string WriteFileAtomically(const std::string& path, const std::string& contents) {
  std::string tmp = path + ".tmp.XXXXXX";
  const int fd = ::mkstemp(&tmp[0]);
  if (fd < 0) {
    return std::string("cannot create a temporary file next to it: ") + std::strerror(errno);
  }
  std::string error;
  const char* p = contents.data();
  std::size_t left = contents.size();
  while (left > 0 && error.empty()) {
    const ssize_t n = ::write(fd, p, left);
    if (n < 0) {
      if (errno == EINTR) continue;
      error = std::string("write failed: ") + std::strerror(errno);
    } else {
      p += n;
      left -= static_cast<std::size_t>(n);
    }
  }
  // mkstemp creates the file 0600; maps and trajectories are meant to be read by other users'
  // tools, so give it the usual 0644.
  if (error.empty() && ::fchmod(fd, 0644) != 0) {
    error = std::string("chmod failed: ") + std::strerror(errno);
  }
  // fsync before rename so that after a crash the name points at complete contents.
  if (error.empty() && ::fsync(fd) != 0) {
    error = std::string("fsync failed: ") + std::strerror(errno);
  }
  if (::close(fd) != 0 && error.empty()) {
    error = std::string("close failed: ") + std::strerror(errno);
  }
  if (error.empty() && std::rename(tmp.c_str(), path.c_str()) != 0) {
    error = std::string("rename into place failed: ") + std::strerror(errno);
  }
  if (!error.empty()) ::unlink(tmp.c_str());
  return error;
}

// The shortest decimal text that reads back as exactly `v` (so files round-trip bit for bit and
// still show 0.05 rather than 0.050000000000000003). Plain decimals where that is short enough
// (50, not 5e+01; 1700000000.25, not 1.70000000025e+09), exponents only for tiny or huge values.
inline std::string FormatDouble(double v) {
  char buf[64];
  if (std::abs(v) >= 1e-4 && std::abs(v) < 1e15) {
    for (int decimals = 0; decimals <= 17; ++decimals) {
      std::snprintf(buf, sizeof(buf), "%.*f", decimals, v);
      if (std::strtod(buf, nullptr) == v) return buf;
    }
  }
  for (int precision = 1; precision <= 17; ++precision) {
    std::snprintf(buf, sizeof(buf), "%.*g", precision, v);
    if (std::strtod(buf, nullptr) == v) break;
  }
  return buf;
}

}  // namespace minibot3d_map_io

#endif  // MINIBOT3D_MAP_IO_FILE_UTIL_H_

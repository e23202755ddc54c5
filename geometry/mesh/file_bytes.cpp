// Reading a model file's bytes; see file_bytes.h.
#include "geometry/mesh/file_bytes.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>

#include <fmt/core.h>

#include "geometry/core/error.h"

namespace geometry {
namespace {

[[noreturn]] void fail(const std::string& path, const std::string& problem) {
  throw InputError(fmt::format("{}: {}", path, problem));
}

}  // namespace

std::string read_file_bytes(const std::string& path) {
  const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
  if (fd < 0) {
    const int error = errno;
    if (error == ENOENT) fail(path, "no such file (check the path)");
    if (error == EACCES) fail(path, "permission denied: cannot read the file");
    fail(path, fmt::format("cannot open the file ({})", std::strerror(error)));
  }
  struct Closer {
    int fd;
    ~Closer() { ::close(fd); }
  } closer{fd};
  struct stat info {};
  if (::fstat(fd, &info) != 0) {
    fail(path, fmt::format("cannot read the file ({})", std::strerror(errno)));
  }
  if (S_ISDIR(info.st_mode)) fail(path, "is a directory, not a model file");
  if (!S_ISREG(info.st_mode)) fail(path, "is not a regular file (a device or pipe?)");

  // One read of the whole file; the parsers work on the bytes in place.
  std::string bytes(static_cast<std::size_t>(info.st_size), '\0');
  std::size_t done = 0;
  while (done < bytes.size()) {
    const ssize_t got = ::read(fd, bytes.data() + done, bytes.size() - done);
    if (got < 0 && errno == EINTR) continue;
    if (got < 0) fail(path, fmt::format("reading failed ({})", std::strerror(errno)));
    if (got == 0) break;  // the file shrank while we read it
    done += static_cast<std::size_t>(got);
  }
  bytes.resize(done);
  return bytes;
}

}  // namespace geometry

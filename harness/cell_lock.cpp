#include "harness/cell_lock.h"

#include <fcntl.h>
#include <sys/file.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <stdexcept>
#include <system_error>

#include <fmt/format.h>

namespace fs = std::filesystem;

namespace sb {

std::optional<CellLock> CellLock::acquire(const fs::path& recordsDir, const std::string& key,
                                          bool wait) {
  const fs::path folder = recordsDir / ".locks";
  std::error_code error;
  fs::create_directories(folder, error);
  const fs::path path = folder / (key + ".lock");
  const int fd = ::open(path.c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0644);
  if (fd < 0)
    throw std::runtime_error(
        fmt::format("cannot create the lock '{}': {}", path.string(), std::strerror(errno)));
  int result;
  do result = ::flock(fd, LOCK_EX | (wait ? 0 : LOCK_NB));
  while (result != 0 && errno == EINTR);
  if (result == 0) return CellLock(fd);
  const int cause = errno;
  ::close(fd);
  if (cause == EWOULDBLOCK && !wait) return std::nullopt;
  throw std::runtime_error(
      fmt::format("cannot lock '{}': {}", path.string(), std::strerror(cause)));
}

CellLock::CellLock(CellLock&& other) noexcept : fd_(other.fd_) {
  other.fd_ = -1;
}

CellLock::~CellLock() {
  if (fd_ >= 0) ::close(fd_);  // closing the last descriptor releases the flock
}

}  // namespace sb

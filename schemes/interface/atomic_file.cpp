#include "schemes/interface/atomic_file.h"

#include <fcntl.h>
#include <stdlib.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <cstring>
#include <stdexcept>
#include <system_error>
#include <thread>

#include <fmt/format.h>

namespace fs = std::filesystem;

namespace sb {

namespace {

// Closes a file descriptor and removes the temporary it belongs to unless released: the one
// place that guarantees a failed write leaves nothing behind.
class TemporaryFile {
 public:
  TemporaryFile(fs::path path, int fd) : path_(std::move(path)), fd_(fd) {}
  TemporaryFile(const TemporaryFile&) = delete;
  TemporaryFile& operator=(const TemporaryFile&) = delete;
  ~TemporaryFile() {
    if (fd_ >= 0) ::close(fd_);
    if (!released_) ::unlink(path_.c_str());
  }
  int fd() const { return fd_; }
  const fs::path& path() const { return path_; }
  // Closes the descriptor, reporting a failed close (which can report a failed write).
  bool close() {
    const int fd = fd_;
    fd_ = -1;
    return ::close(fd) == 0;
  }
  void release() { released_ = true; }

 private:
  fs::path path_;
  int fd_;
  bool released_ = false;
};

[[noreturn]] void throwFileError(std::string_view what, const fs::path& path, int error) {
  throw std::runtime_error(fmt::format("{} '{}': {}", what, path.string(), std::strerror(error)));
}

// A new temporary beside `path`. Its name starts with '.' and does not end in ".json", so a
// reader never takes a leftover temporary for a record.
TemporaryFile createTemporaryBeside(const fs::path& path) {
  static std::atomic<uint64_t> counter{0};
  const auto thread = std::hash<std::thread::id>{}(std::this_thread::get_id());
  for (int attempt = 0; attempt < 100; ++attempt) {
    const fs::path temporary =
        path.parent_path() / fmt::format(".{}.tmp-{}-{:x}-{}", path.filename().string(), getpid(),
                                         thread & 0xffffff, counter.fetch_add(1));
    const int fd = ::open(temporary.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0644);
    if (fd >= 0) return TemporaryFile(temporary, fd);
    if (errno != EEXIST) throwFileError("cannot create a temporary file for", path, errno);
  }
  throwFileError("cannot create a temporary file for", path, EEXIST);
}

void writeAll(int fd, std::string_view data, const fs::path& path) {
  while (!data.empty()) {
    const ssize_t written = ::write(fd, data.data(), data.size());
    if (written < 0) {
      if (errno == EINTR) continue;
      throwFileError("cannot write", path, errno);
    }
    data.remove_prefix(size_t(written));
  }
}

// Makes the rename itself durable; failure only weakens durability, not atomicity.
void syncFolder(const fs::path& folder) {
  const int fd = ::open(folder.empty() ? "." : folder.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
  if (fd < 0) return;
  ::fsync(fd);
  ::close(fd);
}

}  // namespace

void checkReplaceable(const fs::path& path) {
  std::error_code error;
  const fs::file_status status = fs::status(path, error);
  if (status.type() == fs::file_type::not_found) return;
  if (error) throwFileError("cannot inspect", path, error.value());
  if (status.type() != fs::file_type::regular)
    throw std::runtime_error(fmt::format(
        "refusing to replace '{}': it exists and is not a regular file", path.string()));
}

void writeFileAtomically(const fs::path& path, std::string_view contents) {
  std::error_code error;
  if (path.has_parent_path()) {
    fs::create_directories(path.parent_path(), error);
    if (error) throwFileError("cannot create the folder of", path, error.value());
  }
  checkReplaceable(path);
  TemporaryFile temporary = createTemporaryBeside(path);
  writeAll(temporary.fd(), contents, path);
  if (::fsync(temporary.fd()) != 0) throwFileError("cannot sync", path, errno);
  if (!temporary.close()) throwFileError("cannot write", path, errno);
  if (::rename(temporary.path().c_str(), path.c_str()) != 0)
    throwFileError("cannot replace", path, errno);
  temporary.release();
  syncFolder(path.parent_path());
}

void checkWritableFolder(const fs::path& folder) {
  const fs::path at = folder.empty() ? fs::path(".") : folder;
  std::error_code error;
  fs::create_directories(at, error);
  if (error)
    throw std::runtime_error(
        fmt::format("cannot create the folder '{}': {}", at.string(), error.message()));
  std::string probe = (at / ".shadowbench-probe-XXXXXX").string();
  const int fd = ::mkstemp(probe.data());
  if (fd < 0)
    throw std::runtime_error(fmt::format("cannot create files in the folder '{}': {}", at.string(),
                                         std::strerror(errno)));
  ::close(fd);
  ::unlink(probe.c_str());
}

}  // namespace sb

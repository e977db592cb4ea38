// A lock on one cell of a records folder, so that sweeps sharing the folder (a cluster running
// several) share the work instead of each building every cell (issue 11 A10).
#pragma once

#include <filesystem>
#include <optional>
#include <string>

namespace sb {

class CellLock {
 public:
  // flock on <recordsDir>/.locks/<key>.lock. With `wait` false: nullopt when another holder has
  // it. Throws std::runtime_error naming the file when it cannot be created or locked. The lock
  // files stay: removing one while another sweep opens it would let two sweeps hold the lock.
  static std::optional<CellLock> acquire(const std::filesystem::path& recordsDir,
                                         const std::string& key, bool wait);

  CellLock(CellLock&& other) noexcept;
  CellLock& operator=(CellLock&&) = delete;
  CellLock(const CellLock&) = delete;
  ~CellLock();  // releases

 private:
  explicit CellLock(int fd) : fd_(fd) {}
  int fd_ = -1;
};

}  // namespace sb

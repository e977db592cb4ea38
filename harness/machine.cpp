#include "harness/machine.h"

#include <malloc.h>
#include <sys/utsname.h>

#include <algorithm>
#include <cstdio>
#include <fstream>
#include <string>
#include <string_view>
#include <thread>

#include <fmt/format.h>

namespace sb {

namespace {

// The value of the first "key: value" line of a /proc file whose key is `key`, trimmed;
// empty when there is none.
std::string procField(const char* file, std::string_view key) {
  std::ifstream in(file);
  for (std::string line; std::getline(in, line);) {
    const size_t colon = line.find(':');
    if (colon == std::string::npos) continue;
    std::string_view name(line.data(), colon);
    while (!name.empty() && (name.back() == ' ' || name.back() == '\t')) name.remove_suffix(1);
    if (name != key) continue;
    const size_t begin = line.find_first_not_of(" \t", colon + 1);
    if (begin == std::string::npos) return {};
    const size_t end = line.find_last_not_of(" \t\r");
    return line.substr(begin, end - begin + 1);
  }
  return {};
}

// A "/proc" size such as "16314236 kB" in bytes; 0 when absent or malformed.
uint64_t procKilobytes(const char* file, std::string_view key) {
  const std::string value = procField(file, key);
  uint64_t kilobytes = 0;
  bool any = false;
  for (char c : value) {
    if (c < '0' || c > '9') break;
    kilobytes = kilobytes * 10 + uint64_t(c - '0');
    any = true;
  }
  return any ? kilobytes * 1024 : 0;
}

std::string cpuModel() {
  // x86 names the model; other architectures use other keys, or none.
  for (const char* key : {"model name", "Hardware", "cpu model", "Processor", "cpu"}) {
    std::string model = procField("/proc/cpuinfo", key);
    if (!model.empty()) return model;
  }
  return "unknown";
}

std::string operatingSystem() {
  utsname name{};
  if (uname(&name) != 0) return "unknown";
  return fmt::format("{} {} {}", name.sysname, name.release, name.machine);
}

}  // namespace

nlohmann::json machineInfo() {
  return {{"cpu", cpuModel()},
          {"cores", std::thread::hardware_concurrency()},
          {"memory_bytes", procKilobytes("/proc/meminfo", "MemTotal")},
          {"os", operatingSystem()}};
}

std::optional<uint64_t> cgroupMemoryLeft(const std::filesystem::path& cgroupRoot,
                                         const std::filesystem::path& procSelfCgroup) {
  const auto number = [](const std::filesystem::path& file) -> std::optional<uint64_t> {
    std::ifstream value(file);
    uint64_t bytes = 0;
    if (!(value >> bytes)) return std::nullopt;  // absent, or "max"
    return bytes;
  };
  std::optional<uint64_t> left;
  // The least room over a group and its ancestors, up to the hierarchy's root.
  const auto walk = [&](const std::filesystem::path& hierarchy, const std::string& group,
                        const char* limitFile, const char* usageFile) {
    for (std::filesystem::path at = hierarchy / group.substr(1);; at = at.parent_path()) {
      const auto limit = number(at / limitFile), used = number(at / usageFile);
      if (limit && used)
        left = std::min(left.value_or(UINT64_MAX), *limit - std::min(*limit, *used));
      if (at == hierarchy || !at.has_parent_path() || at.parent_path() == at) break;
    }
  };
  // Lines "id:controllers:/path": "0::/path" is the unified (v2) hierarchy; a v1 memory
  // controller has its own, under <root>/memory.
  std::ifstream in(procSelfCgroup);
  for (std::string line; std::getline(in, line);) {
    const size_t first = line.find(':'), second = line.find(':', first + 1);
    if (first == std::string::npos || second == std::string::npos) continue;
    const std::string controllers = line.substr(first + 1, second - first - 1);
    const std::string group = line.substr(second + 1);
    if (!group.starts_with("/")) continue;
    if (controllers.empty())
      walk(cgroupRoot, group, "memory.max", "memory.current");
    else if (controllers == "memory" || controllers.starts_with("memory,") ||
             controllers.find(",memory") != std::string::npos)
      walk(cgroupRoot / "memory", group, "memory.limit_in_bytes", "memory.usage_in_bytes");
  }
  return left;
}

uint64_t availableMemoryBytes() {
  const uint64_t available = procKilobytes("/proc/meminfo", "MemAvailable");
  const auto confined = cgroupMemoryLeft("/sys/fs/cgroup", "/proc/self/cgroup");
  return confined ? std::min(available, *confined) : available;
}
uint64_t currentRssBytes() {
  return procKilobytes("/proc/self/status", "VmRSS");
}
uint64_t peakRssBytes() {
  return procKilobytes("/proc/self/status", "VmHWM");
}

void resetPeakRss() {
  // Heap pages an earlier build freed stay resident until trimmed, and would count in this
  // build's baseline and peak (a sweep builds cell after cell in one process).
  malloc_trim(0);
  // "5" resets VmHWM to the current RSS (Linux ≥ 4.0). Without it the peak includes whatever
  // ran before, which only overstates; nothing to report.
  if (FILE* file = std::fopen("/proc/self/clear_refs", "w")) {
    std::fputs("5", file);
    std::fclose(file);
  }
}

}  // namespace sb

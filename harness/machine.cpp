#include "harness/machine.h"

#include <malloc.h>
#include <sys/utsname.h>

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

uint64_t availableMemoryBytes() {
  return procKilobytes("/proc/meminfo", "MemAvailable");
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

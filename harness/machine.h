// Facts about this machine and this process from /proc: what a record says it ran on, and the
// memory figures builds are checked and measured against (DESIGN §6).
#pragma once

#include <cstdint>
#include <filesystem>
#include <optional>

#include <nlohmann/json.hpp>

namespace sb {

// {"cpu", "cores", "memory_bytes", "os"} of this machine; unknown facts are "unknown" or 0.
nlohmann::json machineInfo();

// What the process's control groups still let it use: the least limit less usage over its
// groups (as /proc/self/cgroup names them: cgroup v2's memory.max and memory.current under
// `cgroupRoot`, v1's memory.limit_in_bytes and memory.usage_in_bytes under <root>/memory) and
// their ancestors; nullopt when no group says. A job that Slurm or systemd confines sees its own
// limit, not the node's free memory.
std::optional<uint64_t> cgroupMemoryLeft(const std::filesystem::path& cgroupRoot,
                                         const std::filesystem::path& procSelfCgroup);

// Memory figures from /proc; 0 where the kernel does not say.
// MemAvailable, or what the process's cgroup still allows where that is less: what a build can
// still use without swapping or being killed.
uint64_t availableMemoryBytes();
uint64_t currentRssBytes();  // VmRSS
void resetPeakRss();         // so that the next peakRssBytes() measures from now on
uint64_t peakRssBytes();     // VmHWM

}  // namespace sb

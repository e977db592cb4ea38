// Facts about this machine and this process from /proc: what a record says it ran on, and the
// memory figures builds are checked and measured against (DESIGN §6).
#pragma once

#include <cstdint>

#include <nlohmann/json.hpp>

namespace sb {

// {"cpu", "cores", "memory_bytes", "os"} of this machine; unknown facts are "unknown" or 0.
nlohmann::json machineInfo();

// Memory figures from /proc; 0 where the kernel does not say.
uint64_t availableMemoryBytes();  // MemAvailable: what a build can still use without swapping
uint64_t currentRssBytes();       // VmRSS
void resetPeakRss();              // so that the next peakRssBytes() measures from now on
uint64_t peakRssBytes();          // VmHWM

}  // namespace sb

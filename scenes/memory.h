// The memory a scene will occupy, estimated before anything is allocated, and the memory the
// machine has for it: a scene that cannot fit is refused with both figures instead of ending in
// std::bad_alloc (or the kernel's OOM killer) after minutes of work.
#pragma once

#include <cstdint>
#include <string_view>

namespace sb::detail {

// MemAvailable of /proc/meminfo in bytes: what can still be allocated without swapping; 0 when
// it cannot be read. The scenes library reads it itself rather than asking the harness for it,
// so that every caller of openScene is protected and scenes/ depends on no other part.
uint64_t availableMemoryBytes();

// Throws a SceneError "<origin>: <what> needs at least X GiB but only Y GiB of memory is
// available; <advice>" when `neededBytes` exceeds `limitBytes`.
void checkFitsInMemory(std::string_view origin, std::string_view what, uint64_t neededBytes,
                       uint64_t limitBytes, std::string_view advice);

}  // namespace sb::detail

// Node headers of the MH family and of CPVS pack a 2-bit flag per child, child k in bits 2k and
// 2k + 1 (SBE16a §4: no child, empty, inner or leaf; Sintorn §4: empty, lit, partial). One
// reading of that packing for every structure.
#pragma once

#include <cstdint>

namespace sb {

constexpr uint32_t childFlag(uint32_t flags, int k) {
  return (flags >> (2 * k)) & 3;
}

}  // namespace sb

// What every structure fuzz target does with a structure that loaded: a loaded structure must
// never read out of bounds at lookup time (SchemeInfo::load's promise), whatever the bytes.
#pragma once

#include "schemes/interface/scheme.h"

namespace sb::fuzz {

// Point and PCF lookups at every texel centre of an 8×8 grid, at the map's edges and just
// outside, over the whole depth range; aborts if an answer is not a fraction in [0, 1].
void exerciseDecoder(const Decoder& decoder);

}  // namespace sb::fuzz

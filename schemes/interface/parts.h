// Builds in parts (DESIGN §5): a map too large to encode at once is cut into square parts, each
// encoded on its own into a part payload (the harness wraps it in a part file), and a merge joins
// the payloads into the scheme's final structure. This is how Kämpe et al. 2015 (§4, sub-volumes)
// and Scandolo & Eisemann 2021 (compressed tiles merged on the CPU) reach 256K² and beyond.
//
// A structure merged from parts answers every query exactly as the whole build does; where a part
// border loses sharing the size may differ, and the scheme's README says by how much.
#pragma once

#include <cstdint>
#include <memory>

#include "schemes/interface/morton.h"
#include "schemes/interface/scheme.h"

namespace sb {

class ByteReader;
class ByteWriter;

// Part `index` of a map cut into parts of side `size` (a power of two dividing R): parts are
// numbered in Morton order, so the harness's tile stream visits them one after another and a
// part's own tiles arrive in Morton order inside it, with absolute texel coordinates.
struct MapPart {
  uint64_t index = 0;
  uint32_t x0 = 0, y0 = 0, size = 0;

  static MapPart of(uint64_t index, uint32_t size) {
    return {index, mortonX(index) * size, mortonY(index) * size, size};
  }
  static uint64_t countFor(const MapInfo& map, uint32_t size) {
    const uint64_t perSide = map.resolution / size;
    return perSide * perSide;
  }
};

// Encodes one part. Tiles are square, lie inside the part, and arrive in Morton order within it.
class PartEncoder {
 public:
  virtual ~PartEncoder() = default;
  virtual void consume(const DualDepthTile& tile, BuildContext& context) = 0;
  // Writes the part's payload; a PartMerger of the same scheme, map and parameters reads it.
  virtual void finish(ByteWriter& out, BuildContext& context) = 0;
};

// Joins part payloads into the final structure. Parts arrive in index order, every part once per
// pass; a payload is validated as a structure file's payload is (throws FormatError naming the
// part). The merger keeps no more than the structure it grows plus what one part needs.
class PartMerger {
 public:
  virtual ~PartMerger() = default;
  virtual void add(const MapPart& part, ByteReader& payload, BuildContext& context) = 0;
  // Asked after every pass over the parts: a merger that would otherwise hold every part at once
  // (the structure's layout depends on all of them) reads them again instead. finish() follows
  // the last pass.
  virtual bool anotherPass(BuildContext&) { return false; }
  virtual std::unique_ptr<Decoder> finish(BuildContext& context) = 0;
};

}  // namespace sb

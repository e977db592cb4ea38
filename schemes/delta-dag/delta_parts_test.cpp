// delta-dag's merge of parts (delta_parts.h) against the whole build: the same bytes.
#include <catch2/catch.hpp>

#include "schemes/interface/serial.h"
#include "tests/support/synthetic_map.h"

namespace sb {
namespace {

using testing::SyntheticMap;

// The merge of parts never holds the whole hierarchy (delta_parts.h), yet finds the packs in the
// whole build's order: the structure must be the whole build's byte for byte (tiles of one size,
// which orders the hierarchy's nodes), with every option that changes how packs are found.
TEST_CASE("a merge of parts writes the whole build's bytes", "[delta-dag][parts]") {
  const SchemeInfo& scheme = findScheme("delta-dag");
  const SyntheticMap blocky = SyntheticMap::blocky(64, DepthMode::Closed, 3, 8);
  const std::vector<SyntheticMap> maps = {SyntheticMap::random(64, DepthMode::Open, 31),
                                          SyntheticMap::random(64, DepthMode::Static, 32), blocky,
                                          SyntheticMap::uniform(64, 0.25f, 0.75f)};
  const std::vector<Params> options = {{},
                                       {{"addresses", "found"}},
                                       {{"symmetry", "none"}},
                                       {{"sharing", "tree"}},
                                       {{"values", "middle"}}};
  for (const SyntheticMap& map : maps)
    for (const Params& params : options)
      for (const uint32_t partSize : {8u, 16u, 32u}) {
        INFO(toString(map.mode) << " parts of " << partSize << " option "
                                << (params.empty() ? "none" : params.begin()->second));
        ByteWriter whole, merged;
        map.build(scheme, params, 8)->save(whole);
        map.buildInParts(scheme, params, 8, partSize)->save(merged);
        CHECK(merged.bytes() == whole.bytes());
      }
}

}  // namespace
}  // namespace sb

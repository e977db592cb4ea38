// The MH family's part payloads (mh_parts.h) as a file format: pinned by golden files, merged
// from them into the whole build's structure, and every truncated or crafted payload refused
// with a FormatError naming the part, the merger keeping what it had (run under the sanitizers
// in CI).
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <iterator>

#include <fmt/format.h>
#include <catch2/catch.hpp>

#include "schemes/interface/parts.h"
#include "schemes/interface/serial.h"
#include "schemes/shared/mh_parts.h"
#include "tests/support/synthetic_map.h"

namespace sb {
namespace {

using testing::NullBuildContext;
using testing::SyntheticMap;

constexpr const char* kMhFamily[] = {"mh", "mmh", "dag-mh"};

// The payloads of every part of `map`, in part order.
std::vector<std::vector<uint8_t>> partPayloads(const SchemeInfo& scheme, const SyntheticMap& map,
                                               uint32_t tileSize, uint32_t partSize) {
  return map.partPayloads(scheme, {}, tileSize, partSize);
}

std::unique_ptr<PartMerger> mergerFor(const SchemeInfo& scheme, const SyntheticMap& map,
                                      uint32_t tileSize, uint32_t partSize) {
  return scheme.makePartMerger(map.info(scheme.kind), scheme.resolve({}),
                               BuildShape{tileSize, partSize});
}

void add(PartMerger& merger, uint64_t index, uint32_t partSize, std::span<const uint8_t> payload) {
  NullBuildContext context;
  ByteReader in(payload);
  merger.add(MapPart::of(index, partSize), in, context);
  in.expectEnd();
}

// Ends a merge whose first pass was fed by hand: the passes the merger asks for, then finish.
std::unique_ptr<Decoder> finishMerge(PartMerger& merger, uint32_t partSize,
                                     const std::vector<std::vector<uint8_t>>& payloads) {
  NullBuildContext context;
  while (merger.anotherPass(context))
    for (uint64_t index = 0; index < payloads.size(); ++index)
      add(merger, index, partSize, payloads[index]);
  return merger.finish(context);
}

// Point answers at each texel's bounds and just beyond them.
std::vector<float> answers(const Decoder& decoder, const SyntheticMap& map) {
  std::vector<Query> queries;
  const float r = float(map.resolution);
  for (uint32_t j = 0; j < map.resolution; ++j)
    for (uint32_t i = 0; i < map.resolution; ++i) {
      const size_t at = size_t(j) * map.resolution + i;
      for (float z : {map.lo[at], std::nextafter(map.lo[at], 2.0f), map.hi[at]})
        if (std::isfinite(z) && z <= 1.0f) queries.push_back({(i + 0.5f) / r, (j + 0.5f) / r, z});
    }
  std::vector<float> got(queries.size());
  decoder.lookup(queries, 1, got);
  return got;
}

std::vector<uint8_t> readFile(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), {}};
}

void writeFile(const std::string& path, const std::vector<uint8_t>& bytes) {
  std::ofstream(path, std::ios::binary)
      .write(reinterpret_cast<const char*>(bytes.data()), std::streamsize(bytes.size()));
}

// Byte offsets in a payload (mh_parts.h).
constexpr size_t kSizeAt = 8, kRootAt = 12, kRootFlagsAt = 24, kCountAt = 25, kNodesAt = 33;
size_t nodeAt(size_t n) {
  return kNodesAt + n * kMhPartNodeBytes;
}

template <class T>
void poke(std::vector<uint8_t>& bytes, size_t at, T value) {
  std::memcpy(bytes.data() + at, &value, sizeof(T));
}
template <class T>
T peek(const std::vector<uint8_t>& bytes, size_t at) {
  T value;
  std::memcpy(&value, bytes.data() + at, sizeof(T));
  return value;
}

}  // namespace

// A 32² map in parts of 16² (tiles of 8²): the four payloads one after another in
// tests/golden/<scheme>.part; regenerate deliberately with SHADOWBENCH_UPDATE_GOLDEN=1 when the
// payload format changes.
TEST_CASE("part payloads match their golden files and merge into the whole build",
          "[mh][parts][format]") {
  const SyntheticMap map = SyntheticMap::random(32, DepthMode::Closed, 42);
  for (const char* name : kMhFamily) {
    const SchemeInfo& scheme = findScheme(name);
    const std::string path = fmt::format("tests/golden/{}.part", name);
    INFO("golden file " << path << " (create it with SHADOWBENCH_UPDATE_GOLDEN=1)");
    std::vector<uint8_t> payloads;
    std::vector<size_t> starts;
    for (const auto& payload : partPayloads(scheme, map, 8, 16)) {
      starts.push_back(payloads.size());
      payloads.insert(payloads.end(), payload.begin(), payload.end());
    }
    starts.push_back(payloads.size());
    if (std::getenv("SHADOWBENCH_UPDATE_GOLDEN")) writeFile(path, payloads);
    const std::vector<uint8_t> golden = readFile(path);
    REQUIRE(!golden.empty());
    REQUIRE(golden == payloads);

    NullBuildContext context;
    auto merger = mergerFor(scheme, map, 8, 16);
    const auto merged = testing::mergePayloads(
        *merger, 4, 16,
        [&](uint64_t index) {
          return std::span(golden).subspan(starts[index], starts[index + 1] - starts[index]);
        },
        context);
    CHECK(answers(*merged, map) == answers(*map.build(scheme, {}, 8), map));
  }
}

TEST_CASE("truncated and crafted part payloads are refused and the merge goes on",
          "[mh][parts][format]") {
  const SyntheticMap map = SyntheticMap::random(64, DepthMode::Closed, 7);
  for (const char* name : kMhFamily) {
    INFO(name);
    const SchemeInfo& scheme = findScheme(name);
    const auto payloads = partPayloads(scheme, map, 16, 32);
    const std::vector<uint8_t>& valid = payloads[2];
    const uint64_t count = peek<uint64_t>(valid, kCountAt);
    REQUIRE(valid.size() == nodeAt(count));
    REQUIRE(count > 8);

    auto merger = mergerFor(scheme, map, 16, 32);
    add(*merger, 0, 32, payloads[0]);
    add(*merger, 1, 32, payloads[1]);
    for (size_t length = 0; length < valid.size(); ++length) {
      INFO("truncated to " << length << " bytes");
      CHECK_THROWS_AS(add(*merger, 2, 32, std::span(valid).first(length)), FormatError);
    }

    // Crafted payloads, each with something a loader must catch.
    const auto firstInner = [&] {
      for (size_t n = 0; n < count; ++n)
        if (valid[nodeAt(n) + 12]) return n;
      FAIL("no inner node");
      return size_t(0);
    }();
    const uint32_t innerFirst = peek<uint32_t>(valid, nodeAt(firstInner) + 8);
    std::vector<std::pair<const char*, std::vector<uint8_t>>> crafted;
    const auto craft = [&](const char* what, auto&& edit) {
      std::vector<uint8_t> bytes = valid;
      edit(bytes);
      crafted.emplace_back(what, std::move(bytes));
    };
    craft("another part side", [](auto& b) { poke<uint32_t>(b, kSizeAt, 16); });
    craft("a node more than the bytes", [&](auto& b) { poke<uint64_t>(b, kCountAt, count + 1); });
    craft("2^40 nodes", [](auto& b) { poke<uint64_t>(b, kCountAt, uint64_t(1) << 40); });
    craft("a childless root over the nodes", [](auto& b) { b[kRootFlagsAt] = 0; });
    craft("lo above hi",
          [&](auto& b) { poke(b, nodeAt(0), peek<uint32_t>(b, nodeAt(0) + 4) + 1); });
    craft("a NaN key", [&](auto& b) { poke<uint32_t>(b, nodeAt(0) + 4, 0x7fc00000u); });
    craft("children after their parent",
          [&](auto& b) { poke<uint32_t>(b, nodeAt(firstInner) + 8, uint32_t(firstInner)); });
    craft("a pack shared by two parents", [&](auto& b) {
      for (size_t n = count; n-- > firstInner + 1;)
        if (b[nodeAt(n) + 12]) return poke<uint32_t>(b, nodeAt(n) + 8, innerFirst);
    });
    craft("an inner node without children", [&](auto& b) { b[nodeAt(firstInner) + 12] = 0; });
    craft("a leaf with children", [&](auto& b) {
      b[nodeAt(firstInner) + 12] = uint8_t(MhChild::Leaf);  // one child, which is inner or not
      for (size_t c = innerFirst; c < count; ++c)
        if (b[nodeAt(c) + 12]) return poke<uint32_t>(b, nodeAt(firstInner) + 8, uint32_t(c));
    });
    for (const auto& [what, bytes] : crafted) {
      INFO(what);
      std::string refusal = "accepted";
      try {
        add(*merger, 2, 32, bytes);
      } catch (const FormatError& error) {
        refusal = error.what();
      }
      CHECK_THAT(refusal, Catch::Contains(fmt::format("{} part 2: ", name)));
    }
    CHECK_THROWS_AS(add(*merger, 3, 32, payloads[3]), std::invalid_argument);

    // Nothing refused reached the merger: it ends as the whole build.
    add(*merger, 2, 32, valid);
    add(*merger, 3, 32, payloads[3]);
    CHECK(answers(*finishMerge(*merger, 32, payloads), map) ==
          answers(*map.build(scheme, {}, 16), map));
  }
}

// delta-dag's merge reads only the parts' roots in its first pass (readMhPartRoot) and every node
// in its second: a truncated payload is refused in either, a damaged root in the first, damaged
// nodes or another root in the second, with the part named, and the merge goes on to the whole
// build's answers.
TEST_CASE("a merge reading the parts' roots first refuses damaged nodes in its second pass",
          "[mh][parts][format]") {
  const SyntheticMap map = SyntheticMap::random(64, DepthMode::Closed, 7);
  const SchemeInfo& scheme = findScheme("delta-dag");
  const auto payloads = partPayloads(scheme, map, 16, 32);
  const std::vector<uint8_t>& valid = payloads[2];
  const uint64_t count = peek<uint64_t>(valid, kCountAt);
  REQUIRE(count > 8);
  auto merger = mergerFor(scheme, map, 16, 32);
  NullBuildContext context;
  add(*merger, 0, 32, payloads[0]);
  add(*merger, 1, 32, payloads[1]);
  const auto refusal = [&](std::span<const uint8_t> bytes) {
    try {
      add(*merger, 2, 32, bytes);
    } catch (const FormatError& error) {
      return std::string(error.what());
    }
    return std::string("accepted");
  };
  for (size_t length = 0; length < valid.size(); ++length) {
    INFO("first pass, truncated to " << length << " bytes");
    CHECK_THROWS_AS(add(*merger, 2, 32, std::span(valid).first(length)), FormatError);
  }
  std::vector<uint8_t> lo = valid;
  poke(lo, nodeAt(0), peek<uint32_t>(lo, nodeAt(0) + 4) + 1);
  std::vector<uint8_t> rootLo = valid;
  poke(rootLo, kRootAt, peek<uint32_t>(rootLo, kRootAt + 4) + 1);  // lo above hi
  CHECK_THAT(refusal(rootLo), Catch::Contains("delta-dag part 2: the part's root"));
  add(*merger, 2, 32, valid);
  add(*merger, 3, 32, payloads[3]);
  REQUIRE(merger->anotherPass(context));
  add(*merger, 0, 32, payloads[0]);
  add(*merger, 1, 32, payloads[1]);
  for (size_t length = 0; length < valid.size(); ++length) {
    INFO("second pass, truncated to " << length << " bytes");
    CHECK_THROWS_AS(add(*merger, 2, 32, std::span(valid).first(length)), FormatError);
  }
  std::vector<uint8_t> childless = valid;
  childless[kRootFlagsAt] = 0;
  // A valid payload, but not the one the first pass read: its root's interval narrower.
  std::vector<uint8_t> changed = valid;
  const uint32_t rootLoKey = peek<uint32_t>(changed, kRootAt),
                 rootHiKey = peek<uint32_t>(changed, kRootAt + 4);
  REQUIRE(rootLoKey > 0);
  rootHiKey > rootLoKey ? poke(changed, kRootAt + 4, rootLoKey)
                        : poke(changed, kRootAt, rootLoKey - 1);
  CHECK_THAT(refusal(changed), Catch::Contains("delta-dag part 2: its root is not the one"));
  for (const auto& [what, bytes] :
       {std::pair{"lo above hi", lo}, {"a childless root", childless}}) {
    INFO(what);
    CHECK_THAT(refusal(bytes), Catch::Contains("delta-dag part 2: "));
  }
  add(*merger, 2, 32, valid);
  add(*merger, 3, 32, payloads[3]);
  CHECK_FALSE(merger->anotherPass(context));
  CHECK(answers(*merger->finish(context), map) == answers(*map.build(scheme, {}, 16), map));
}

// Flipped bits that still form a valid tree merge into a structure that answers other depths:
// a structure the scheme's own loader accepts, and whose every lookup stays in bounds (the
// sanitizers watch).
TEST_CASE("part payloads with a flipped bit are refused or merge into a sound structure",
          "[mh][parts][format]") {
  const SyntheticMap map = SyntheticMap::random(32, DepthMode::Static, 8);
  for (const char* name : kMhFamily) {
    INFO(name);
    const SchemeInfo& scheme = findScheme(name);
    const auto payloads = partPayloads(scheme, map, 8, 16);
    size_t refused = 0;
    const size_t stride = payloads[1].size() / 512 + 1;
    for (size_t at = 0; at < payloads[1].size(); at += stride) {
      std::vector<std::vector<uint8_t>> corrupted = payloads;
      corrupted[1][at] ^= uint8_t(1u << (at % 8));
      auto merger = mergerFor(scheme, map, 8, 16);
      add(*merger, 0, 16, payloads[0]);
      try {
        add(*merger, 1, 16, corrupted[1]);
      } catch (const FormatError&) {
        ++refused;
        continue;
      }
      add(*merger, 2, 16, payloads[2]);
      add(*merger, 3, 16, payloads[3]);
      // The scheme's loader, which validates everything, takes what the merge built.
      const auto merged = finishMerge(*merger, 16, corrupted);
      ByteWriter saved;
      merged->save(saved);
      ByteReader in(saved.bytes());
      const auto loaded = scheme.load(in, map.info(scheme.kind), scheme.resolve({}));
      in.expectEnd();
      CHECK(answers(*loaded, map) == answers(*merged, map));
    }
    CHECK(refused > 0);
  }
}

// buildBytes of a build in parts: beyond 16K² the hierarchy's floor grows as R (mh_parts.cpp),
// so doubling R doubles the merge's estimate; a larger part costs its encoder more.
TEST_CASE("estimates of builds in parts grow as R beyond 16K² and follow the part size",
          "[mh][parts]") {
  for (const char* name : kMhFamily) {
    INFO(name);
    const SchemeInfo& scheme = findScheme(name);
    const auto bytes = [&](uint32_t resolution, uint32_t partSize) {
      return double(scheme.buildBytes({resolution, 0, DepthMode::Closed}, scheme.resolve({}),
                                      {512, partSize}));
    };
    const double ratio = bytes(1u << 18, 1u << 12) / bytes(1u << 17, 1u << 12);
    CHECK(ratio > 1.9);
    CHECK(ratio < 2.1);
    CHECK(bytes(1u << 16, 1u << 15) > bytes(1u << 16, 1u << 12));
  }
}

}  // namespace sb

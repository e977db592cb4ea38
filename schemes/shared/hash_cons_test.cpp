// The hash-consing index: equal nodes get one id, different ones different ids even when their
// hashes collide, and ids survive the index's growth.
#include <catch2/catch.hpp>

#include <vector>

#include "schemes/shared/hash_cons.h"

using sb::HashConsIndex;

TEST_CASE("hash-consing gives equal nodes one id across growth and collisions", "[hash_cons]") {
  HashConsIndex index;
  std::vector<uint64_t> stored;  // id → the node's content
  const auto add = [&](uint64_t node, uint64_t hash) {
    const auto [id, added] =
        index.findOrAdd(hash, [&](uint32_t other) { return stored[other] == node; });
    if (added) {
      REQUIRE(id == stored.size());
      stored.push_back(node);
    }
    return id;
  };
  // 5000 nodes, hashed into only 7 values so that most probes collide; past 1024 slots the index
  // grows several times.
  for (uint64_t node = 0; node < 5000; ++node) CHECK(add(node, node % 7) == node);
  for (uint64_t node = 0; node < 5000; node += 13) CHECK(add(node, node % 7) == node);
  CHECK(index.count() == 5000);
  CHECK(add(5000, 5000 % 7) == 5000);
}

TEST_CASE("prefetch hints name the id a lookup meets first, and change nothing", "[hash_cons]") {
  HashConsIndex index;
  std::vector<uint32_t> named;
  const auto remember = [&](uint32_t id) { named.push_back(id); };
  index.prefetchSlot(42);
  index.prefetchNamed(42, remember);  // an empty index names nothing
  CHECK(named.empty());
  const auto same = [](uint32_t) { return true; };
  CHECK(index.findOrAdd(42, same) == std::pair<uint32_t, bool>{0, true});
  CHECK(index.findOrAdd(7, same) == std::pair<uint32_t, bool>{1, true});
  index.prefetchNamed(7, remember);
  index.prefetchNamed(42, remember);
  index.prefetchNamed(43, remember);  // an empty slot
  CHECK(named == std::vector<uint32_t>{1, 0});
  CHECK(index.count() == 2);
  CHECK(index.findOrAdd(42, same) == std::pair<uint32_t, bool>{0, false});
}

// Resolutions and tile sizes as the user writes them.
#include <string>

#include <catch2/catch.hpp>

#include "harness/resolution.h"

using namespace sb;

TEST_CASE("resolutions are read with K = 1024 and M = 1024², either case") {
  CHECK(parseResolution("8") == 8);
  CHECK(parseResolution("4096") == 4096);
  CHECK(parseResolution("4K") == 4096);
  CHECK(parseResolution("4k") == 4096);
  CHECK(parseResolution("64K") == 65536);
  CHECK(parseResolution("1024K") == 1048576);
  CHECK(parseResolution("1M") == 1048576);
  CHECK(parseResolution("1m") == 1048576);
}

TEST_CASE("a resolution that is not a power of two from 8 to 1024K is refused by name") {
  for (const char* text : {"", "K", "M", "0", "0K", "1.5K", "3000", "4", "2M", "2048K", "-4K",
                           "4KK", " 4K", "4K ", "0x100", "99999999999", "1G"}) {
    INFO("'" << text << "'");
    CHECK_THROWS_WITH(parseResolution(text),
                      Catch::Contains(std::string("resolution '") + text + "'") &&
                          Catch::Contains("power of two from 8 to 1024K"));
  }
}

TEST_CASE("every resolution's label reads back as that resolution") {
  for (uint32_t r = 8; r <= (1u << 20); r *= 2) CHECK(parseResolution(resolutionLabel(r)) == r);
  CHECK(resolutionLabel(512) == "512");
  CHECK(resolutionLabel(4096) == "4K");
  CHECK(resolutionLabel(1u << 20) == "1024K");
}

TEST_CASE("a tile size is 0 (the default) or a power of two from 8 to the resolution") {
  for (uint32_t tile : {0u, 8u, 64u, 1024u}) CHECK_NOTHROW(checkTileSize(tile, 1024));
  for (uint32_t tile : {1u, 4u, 12u, 513u, 2048u})
    CHECK_THROWS_WITH(
        checkTileSize(tile, 1024),
        Catch::Contains("tile size " + std::to_string(tile) + " ") && Catch::Contains("[8, 1024]"));
}

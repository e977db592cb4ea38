// Scheme parameters: every rule lives on the registry row and is checked where values are
// resolved; schemes read typed values; every registered row's defaults and sweep values pass
// its own rules (so `sweep` refuses nothing a row offers, and accepts nothing it forbids).
#include <catch2/catch.hpp>

#include <bit>

#include "schemes/interface/scheme.h"

using namespace sb;

namespace {

std::vector<ParamSpec> demoSpecs() {
  return {ParamSpec::integer("treelet", "treelet height", 4, 2, 5, {2, 3, 4, 5}),
          ParamSpec::integer("block", "block side", 64, 8, 1024, {32, 64})
              .satisfying("a power of two",
                          [](int64_t side) { return std::has_single_bit(uint64_t(side)); }),
          ParamSpec::choice("layout", "leaf layout", "4x4x4", {"4x4x4", "8x8x1"})};
}

std::string message(const Params& given) {
  try {
    ParamValues::resolve("demo", demoSpecs(), given);
  } catch (const ParamError& error) {
    return error.what();
  }
  return "no error";
}

}  // namespace

TEST_CASE("parameters resolve to typed values with their defaults", "[params]") {
  const ParamValues values = ParamValues::resolve("demo", demoSpecs(), {{"layout", "8x8x1"}});
  CHECK(values.integer("treelet") == 4);
  CHECK(values.integer("block") == 64);
  CHECK(values.choice("layout") == "8x8x1");
  CHECK(values.text() == Params{{"block", "64"}, {"layout", "8x8x1"}, {"treelet", "4"}});
  CHECK(values.scheme() == "demo");
  // Asking for what the row does not declare, or for the wrong type, is the scheme's bug.
  CHECK_THROWS_AS(values.integer("colour"), std::logic_error);
  CHECK_THROWS_AS(values.integer("layout"), std::logic_error);
  CHECK_THROWS_AS(values.choice("treelet"), std::logic_error);
}

TEST_CASE("invalid values name the scheme, the parameter and the rule", "[params]") {
  CHECK_THAT(message({{"treelet", "9"}}), Catch::Contains("'demo'") &&
                                              Catch::Contains("'treelet'") &&
                                              Catch::Contains("[2, 5]"));
  CHECK_THAT(message({{"treelet", "4x"}}), Catch::Contains("'treelet'"));
  CHECK_THAT(message({{"treelet", "4.0"}}), Catch::Contains("'treelet'"));
  CHECK_THAT(message({{"treelet", ""}}), Catch::Contains("'treelet'"));
  CHECK_THAT(message({{"block", "48"}}),
             Catch::Contains("'block'") && Catch::Contains("a power of two"));
  CHECK_THAT(message({{"layout", "2x2"}}), Catch::Contains("'layout'") && Catch::Contains("8x8x1"));
  CHECK_THAT(message({{"colour", "red"}}), Catch::Contains("no parameter 'colour'"));
  CHECK(message({{"block", "128"}}) == "no error");
}

TEST_CASE("every registered row's defaults and sweep values pass its own rules", "[params]") {
  REQUIRE(!schemes().empty());
  for (const SchemeInfo& scheme : schemes()) {
    INFO(scheme.name);
    CHECK_NOTHROW(scheme.resolve({}));
    for (const ParamSpec& spec : scheme.params)
      for (const std::string& value : spec.sweep) {
        INFO(spec.name << "=" << value);
        CHECK(scheme.resolve({{spec.name, value}}).text().at(spec.name) == value);
      }
  }
}

TEST_CASE("rules a row states are enforced for its scheme", "[params][regression]") {
  // sm-zstd's power-of-two block was checked only inside the encoder, so `sweep` let it
  // through to the middle of a sweep.
  CHECK_THROWS_WITH(findScheme("sm-zstd").resolve({{"block", "48"}}),
                    Catch::Contains("'block'") && Catch::Contains("power of two"));
  CHECK_THROWS_AS(findScheme("dag-mh").resolve({{"chunk-size", "48"}}), ParamError);
}

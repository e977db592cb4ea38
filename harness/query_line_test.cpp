// The `query` line grammar (issue 11 A5): exactly `x y z [k]`, every refusal naming the line and
// quoting at most its first 80 characters.
#include <catch2/catch.hpp>

#include <string>

#include "harness/query_line.h"

using namespace sb;

namespace {

// The message parseQueryLine throws for `line`, or "accepted" when it does not throw.
std::string refusal(std::string_view line, uint64_t number = 1) {
  try {
    parseQueryLine(line, number);
  } catch (const std::invalid_argument& error) {
    return error.what();
  }
  return "accepted";
}

}  // namespace

TEST_CASE("a query line of three or four fields is read exactly") {
  const auto three = parseQueryLine("0.5 0.25 0.3", 1);
  REQUIRE(three);
  CHECK(three->query.x == 0.5f);
  CHECK(three->query.y == 0.25f);
  CHECK(three->query.z == 0.3f);
  CHECK(three->filter == 1);

  const auto four = parseQueryLine("\t 0.125   1e-1 -0 17 \r", 1);
  REQUIRE(four);
  CHECK(four->query.x == 0.125f);
  CHECK(four->query.y == 0.1f);
  CHECK(four->query.z == 0.0f);
  CHECK(four->filter == 17);
}

TEST_CASE("a blank query line is skipped, not refused") {
  CHECK_FALSE(parseQueryLine("", 1));
  CHECK_FALSE(parseQueryLine(" \t\r ", 1));
}

TEST_CASE("trailing fields are refused, not ignored") {
  CHECK(refusal("0.5 0.5 0.3 9 junk", 4) ==
        "query line 4: expected 'x y z [k]', found 5 fields: '0.5 0.5 0.3 9 junk'");
  CHECK(refusal("0.5 0.5", 2) == "query line 2: expected 'x y z [k]', found 2 fields: '0.5 0.5'");
}

TEST_CASE("a filter size with a fraction or exponent is refused, not truncated") {
  CHECK(refusal("0.5 0.5 0.3 9.7", 3) == "query line 3: k is not an integer: '0.5 0.5 0.3 9.7'");
  CHECK(refusal("0.5 0.5 0.3 9e0") == "query line 1: k is not an integer: '0.5 0.5 0.3 9e0'");
  CHECK(refusal("0.5 0.5 0.3 4") ==
        "query line 1: k is not an odd filter size in [1, 17]: '0.5 0.5 0.3 4'");
  CHECK(refusal("0.5 0.5 0.3 99999999999") ==
        "query line 1: k is not an odd filter size in [1, 17]: '0.5 0.5 0.3 99999999999'");
}

TEST_CASE("a coordinate followed by other characters is refused with the line number") {
  CHECK(refusal("0.5 0.5 0.3abc", 12) == "query line 12: z is not a number: '0.5 0.5 0.3abc'");
  CHECK(refusal("x 0.5 0.3", 7) == "query line 7: x is not a number: 'x 0.5 0.3'");
  CHECK(refusal("0.5 0,5 0.3") == "query line 1: y is not a number: '0.5 0,5 0.3'");
}

TEST_CASE("non-finite and out-of-range coordinates are refused") {
  CHECK(refusal("nan 0.5 0.3") == "query line 1: x is not finite: 'nan 0.5 0.3'");
  CHECK(refusal("0.5 -inf 0.3") == "query line 1: y is not finite: '0.5 -inf 0.3'");
  CHECK(refusal("0.5 0.5 infinity") == "query line 1: z is not finite: '0.5 0.5 infinity'");
  CHECK(refusal("0.5 0.5 1e39") == "query line 1: z is out of range: '0.5 0.5 1e39'");
  CHECK(refusal("0.5 0.5 1e39x") == "query line 1: z is not a number: '0.5 0.5 1e39x'");
}

TEST_CASE("a refused long line is quoted by its first 80 characters only") {
  const std::string line = "0.5 0.5 0.3 " + std::string(1000, '7') + "x";
  const std::string message = refusal(line, 99);
  CHECK(message == "query line 99: k is not an integer: '" + line.substr(0, 80) + "'");
  CHECK(message.size() < 140);
}

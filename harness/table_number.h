// The one formatter of the numbers tables print. scripts/ format table numbers in one Python
// function; both are checked against tests/golden/number_format.tsv.
#pragma once

#include <optional>
#include <string>
#include <string_view>

namespace sb {

enum class NumberKind {
  Significant,  // sizes, percentages, times, rates: 3 significant digits, "0.125", "38.2", "131072"
  Count,        // counts of queries: an SI prefix and no unit, "12.3M"
  Integer,      // counts shown whole: mismatches, "5"
};

// As the golden file names the kinds: "significant", "count", "integer"; nullopt otherwise.
std::optional<NumberKind> numberKindFromString(std::string_view name);

// A value that is not finite is "?".
std::string formatTableNumber(double value, NumberKind kind);

}  // namespace sb

// One line of the `query` subcommand's input: `x y z` or `x y z k`, nothing more. Anything else
// is refused with the line's number, so that a typo is never answered as some other query.
#pragma once

#include <cstdint>
#include <optional>
#include <string_view>

#include "schemes/interface/scheme.h"

namespace sb {

struct QueryLine {
  Query query{};
  int filter = 1;
};

// nullopt for a blank line (only spaces/tabs/CR). A line is accepted only if it is exactly
// `x y z` or `x y z k`: finite floats, k an integer written without fraction or exponent (and a
// filter size a lookup accepts). Throws std::invalid_argument:
// "query line N: <why>: '<first 80 chars of the line>'".
std::optional<QueryLine> parseQueryLine(std::string_view line, uint64_t lineNumber);

}  // namespace sb

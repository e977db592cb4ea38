#include "harness/table_number.h"

#include <algorithm>
#include <cmath>

#include <fmt/format.h>

#include "harness/progress.h"

namespace sb {

std::optional<NumberKind> numberKindFromString(std::string_view name) {
  if (name == "significant") return NumberKind::Significant;
  if (name == "count") return NumberKind::Count;
  if (name == "integer") return NumberKind::Integer;
  return std::nullopt;
}

std::string formatTableNumber(double value, NumberKind kind) {
  if (!std::isfinite(value)) return "?";
  switch (kind) {
    case NumberKind::Significant:
      return formatSignificant(value, 3);
    case NumberKind::Count: {
      std::string text = formatSi(value, "");
      text.erase(std::remove(text.begin(), text.end(), ' '), text.end());
      return text;
    }
    case NumberKind::Integer:
      return fmt::format("{:.0f}", value);
  }
  return "?";
}

}  // namespace sb

#include "harness/query_line.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <stdexcept>
#include <string>
#include <system_error>
#include <vector>

#include <fmt/format.h>

#include "schemes/interface/lightspace.h"

namespace sb {
namespace {

constexpr std::string_view kBlank = " \t\r";
// Errors quote the line, but a line may be megabytes of garbage; the start identifies it.
constexpr size_t kQuotedCharacters = 80;

std::vector<std::string_view> fields(std::string_view line) {
  std::vector<std::string_view> result;
  for (size_t start = line.find_first_not_of(kBlank); start != std::string_view::npos;) {
    const size_t end = std::min(line.find_first_of(kBlank, start), line.size());
    result.push_back(line.substr(start, end - start));
    start = line.find_first_not_of(kBlank, end);
  }
  return result;
}

// Why `text` is not a finite float, or nullptr when it is one (stored in `value`). The reasons
// do not repeat the field: the error quotes the line, and a field may be megabytes long.
// from_chars, unlike istream >> float, reports a field that only starts with a number.
const char* readCoordinate(std::string_view text, float& value) {
  const auto [end, error] = std::from_chars(text.data(), text.data() + text.size(), value);
  const bool outOfRange = error == std::errc::result_out_of_range;
  if ((error != std::errc() && !outOfRange) || end != text.data() + text.size())
    return "is not a number";
  if (outOfRange) return "is out of range";
  if (!std::isfinite(value)) return "is not finite";
  return nullptr;
}

const char* readFilter(std::string_view text, int& value) {
  const auto [end, error] = std::from_chars(text.data(), text.data() + text.size(), value);
  const bool outOfRange = error == std::errc::result_out_of_range;
  if ((error != std::errc() && !outOfRange) || end != text.data() + text.size())
    return "is not an integer";
  if (outOfRange || !validFilterSize(value)) return "is not an odd filter size in [1, 17]";
  return nullptr;
}

}  // namespace

std::optional<QueryLine> parseQueryLine(std::string_view line, uint64_t lineNumber) {
  const auto fail = [&](std::string_view why) {
    return std::invalid_argument(
        fmt::format("query line {}: {}: '{}'", lineNumber, why, line.substr(0, kQuotedCharacters)));
  };
  const std::vector<std::string_view> parts = fields(line);
  if (parts.empty()) return std::nullopt;
  if (parts.size() != 3 && parts.size() != 4)
    throw fail(fmt::format("expected 'x y z [k]', found {} fields", parts.size()));
  QueryLine result;
  float* coordinates[] = {&result.query.x, &result.query.y, &result.query.z};
  constexpr const char* kNames[] = {"x", "y", "z"};
  for (int i = 0; i < 3; ++i)
    if (const char* why = readCoordinate(parts[i], *coordinates[i]))
      throw fail(fmt::format("{} {}", kNames[i], why));
  if (parts.size() == 4)
    if (const char* why = readFilter(parts[3], result.filter)) throw fail(fmt::format("k {}", why));
  return result;
}

}  // namespace sb

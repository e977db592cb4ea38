// Scheme parameters: their specs, declared on a scheme's registry row (as lzbench's codec table
// declares levels), and their resolved values, checked once where a build or a load starts and
// handed to the scheme typed.
#pragma once

#include <cstdint>
#include <functional>
#include <map>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

namespace sb {

// Parameter values by name, as text: what a user writes (-p name=value), what records and
// structure headers store.
using Params = std::map<std::string, std::string, std::less<>>;

// A scheme parameter error names the scheme and the parameter.
class ParamError : public std::invalid_argument {
 public:
  using std::invalid_argument::invalid_argument;
};

// One parameter: an integer in [min, max] (optionally with a further rule) or one of a set of
// named choices. `sweep` lists the values a parameter sweep visits. Built with the named
// constructors, so that a row reads as what it declares.
struct ParamSpec {
  std::string name;
  std::string help;
  std::string defaultValue;
  int64_t min = 0, max = 0;          // integer parameters
  std::vector<std::string> choices;  // choice parameters; empty for integers
  std::vector<std::string> sweep;
  // A rule an integer must follow beyond its range, and how the error message names it.
  std::function<bool(int64_t)> rule;
  std::string ruleText;

  static ParamSpec integer(std::string name, std::string help, int64_t defaultValue, int64_t min,
                           int64_t max, std::vector<int64_t> sweep = {});
  static ParamSpec choice(std::string name, std::string help, std::string defaultValue,
                          std::vector<std::string> choices, std::vector<std::string> sweep = {});
  // E.g. .satisfying("a power of two", isPowerOfTwo): checked wherever the value is.
  ParamSpec&& satisfying(std::string text, std::function<bool(int64_t)> check) &&;

  bool isChoice() const { return !choices.empty(); }
};

// Every parameter of one scheme with a value that passed its spec: what a scheme's memory
// estimate, encoder and loader receive. Asking for a name the scheme does not declare, or an
// integer of a choice, is a bug in the scheme and throws std::logic_error.
class ParamValues {
 public:
  int64_t integer(std::string_view name) const;
  const std::string& choice(std::string_view name) const;
  // name → value as text, every parameter present: for records and structure headers.
  const Params& text() const { return text_; }
  const std::string& scheme() const { return scheme_; }

  // Checks `given` against `specs` (unknown names, ranges, choices, rules) and fills in the
  // defaults; throws ParamError naming `scheme` and the parameter.
  static ParamValues resolve(std::string_view scheme, const std::vector<ParamSpec>& specs,
                             const Params& given);

 private:
  std::string scheme_;
  Params text_;
  std::map<std::string, int64_t, std::less<>> integers_;
};

}  // namespace sb

#include "schemes/interface/params.h"

#include <algorithm>
#include <charconv>

#include <fmt/format.h>

namespace sb {

namespace {

const ParamSpec& findSpec(std::string_view scheme, const std::vector<ParamSpec>& specs,
                          std::string_view name) {
  for (const ParamSpec& spec : specs)
    if (spec.name == name) return spec;
  std::string known;
  for (const ParamSpec& spec : specs) known += (known.empty() ? "" : ", ") + spec.name;
  throw ParamError(fmt::format("scheme '{}' has no parameter '{}' (its parameters: {})", scheme,
                               name, known.empty() ? "none" : known));
}

// The value as an integer (integer parameters) after every check of its spec.
int64_t checkedInteger(std::string_view scheme, const ParamSpec& spec, std::string_view value) {
  int64_t parsed = 0;
  const auto [end, error] = std::from_chars(value.data(), value.data() + value.size(), parsed);
  if (error != std::errc() || end != value.data() + value.size() || parsed < spec.min ||
      parsed > spec.max)
    throw ParamError(
        fmt::format("scheme '{}': parameter '{}' must be an integer in [{}, {}], got '{}'", scheme,
                    spec.name, spec.min, spec.max, value));
  if (spec.rule && !spec.rule(parsed))
    throw ParamError(fmt::format("scheme '{}': parameter '{}' must be {}, got '{}'", scheme,
                                 spec.name, spec.ruleText, value));
  return parsed;
}

void checkChoice(std::string_view scheme, const ParamSpec& spec, std::string_view value) {
  if (std::find(spec.choices.begin(), spec.choices.end(), value) == spec.choices.end())
    throw ParamError(fmt::format("scheme '{}': parameter '{}' must be one of {}, got '{}'", scheme,
                                 spec.name, fmt::join(spec.choices, ", "), value));
}

}  // namespace

ParamSpec ParamSpec::integer(std::string name, std::string help, int64_t defaultValue, int64_t min,
                             int64_t max, std::vector<int64_t> sweep) {
  ParamSpec spec;
  spec.name = std::move(name);
  spec.help = std::move(help);
  spec.defaultValue = std::to_string(defaultValue);
  spec.min = min;
  spec.max = max;
  for (int64_t value : sweep) spec.sweep.push_back(std::to_string(value));
  return spec;
}

ParamSpec ParamSpec::choice(std::string name, std::string help, std::string defaultValue,
                            std::vector<std::string> choices, std::vector<std::string> sweep) {
  ParamSpec spec;
  spec.name = std::move(name);
  spec.help = std::move(help);
  spec.defaultValue = std::move(defaultValue);
  spec.choices = std::move(choices);
  spec.sweep = std::move(sweep);
  return spec;
}

ParamSpec&& ParamSpec::satisfying(std::string text, std::function<bool(int64_t)> check) && {
  ruleText = std::move(text);
  rule = std::move(check);
  return std::move(*this);
}

int64_t ParamValues::integer(std::string_view name) const {
  const auto it = integers_.find(name);
  if (it == integers_.end())
    throw std::logic_error(fmt::format(
        "scheme '{}' asked for integer parameter '{}', which it does not declare", scheme_, name));
  return it->second;
}

const std::string& ParamValues::choice(std::string_view name) const {
  const auto it = text_.find(name);
  if (it == text_.end() || integers_.count(name))
    throw std::logic_error(fmt::format(
        "scheme '{}' asked for choice parameter '{}', which it does not declare", scheme_, name));
  return it->second;
}

ParamValues ParamValues::resolve(std::string_view scheme, const std::vector<ParamSpec>& specs,
                                 const Params& given) {
  for (const auto& [name, value] : given) findSpec(scheme, specs, name);
  ParamValues values;
  values.scheme_ = std::string(scheme);
  for (const ParamSpec& spec : specs) {
    const auto it = given.find(spec.name);
    const std::string& value = it == given.end() ? spec.defaultValue : it->second;
    if (spec.isChoice())
      checkChoice(scheme, spec, value);
    else
      values.integers_[spec.name] = checkedInteger(scheme, spec, value);
    values.text_[spec.name] = value;
  }
  return values;
}

}  // namespace sb

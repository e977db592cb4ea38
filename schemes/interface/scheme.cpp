#include "schemes/interface/scheme.h"

#include "schemes/interface/lightspace.h"

#include <algorithm>
#include <charconv>

#include <fmt/format.h>

namespace sb {

std::string_view toString(DepthMode mode) {
  switch (mode) {
    case DepthMode::Open:
      return "open";
    case DepthMode::Closed:
      return "closed";
    case DepthMode::Static:
      return "static";
  }
  return "?";
}

DepthMode depthModeFromString(std::string_view name) {
  for (DepthMode mode : {DepthMode::Open, DepthMode::Closed, DepthMode::Static})
    if (toString(mode) == name) return mode;
  throw std::invalid_argument(
      fmt::format("unknown depth mode '{}' (expected open, closed or static)", name));
}

std::string_view toString(SchemeKind kind) {
  return kind == SchemeKind::Depth ? "depth" : "voxel";
}

uint64_t totalBytes(const SizeBreakdown& sizes) {
  uint64_t total = 0;
  for (const auto& [component, bytes] : sizes) total += bytes;
  return total;
}

namespace {

const ParamSpec& findParam(const SchemeInfo& scheme, std::string_view name) {
  for (const ParamSpec& spec : scheme.params)
    if (spec.name == name) return spec;
  std::string known;
  for (const ParamSpec& spec : scheme.params) known += (known.empty() ? "" : ", ") + spec.name;
  throw ParamError(fmt::format("scheme '{}' has no parameter '{}' (its parameters: {})",
                               scheme.name, name, known.empty() ? "none" : known));
}

void checkValue(const SchemeInfo& scheme, const ParamSpec& spec, const std::string& value) {
  if (!spec.choices.empty()) {
    if (std::find(spec.choices.begin(), spec.choices.end(), value) != spec.choices.end()) return;
    throw ParamError(fmt::format("scheme '{}': parameter '{}' must be one of {}, got '{}'",
                                 scheme.name, spec.name, fmt::join(spec.choices, ", "), value));
  }
  int64_t parsed = 0;
  const auto [end, error] = std::from_chars(value.data(), value.data() + value.size(), parsed);
  if (error != std::errc() || end != value.data() + value.size() || parsed < spec.min ||
      parsed > spec.max)
    throw ParamError(
        fmt::format("scheme '{}': parameter '{}' must be an integer in [{}, {}], got '{}'",
                    scheme.name, spec.name, spec.min, spec.max, value));
}

std::vector<SchemeInfo>& registry() {
  static std::vector<SchemeInfo> all;
  return all;
}

}  // namespace

Params SchemeInfo::resolve(const Params& given) const {
  Params resolved;
  for (const auto& [name, value] : given) checkValue(*this, findParam(*this, name), value);
  for (const ParamSpec& spec : params) {
    auto it = given.find(spec.name);
    resolved[spec.name] = it == given.end() ? spec.defaultValue : it->second;
  }
  return resolved;
}

int64_t SchemeInfo::integer(const Params& resolved, std::string_view param) const {
  const ParamSpec& spec = findParam(*this, param);
  auto it = resolved.find(param);
  const std::string value = it == resolved.end() ? spec.defaultValue : it->second;
  checkValue(*this, spec, value);
  return std::stoll(value);
}

const std::vector<SchemeInfo>& schemes() {
  return registry();
}

const SchemeInfo& findScheme(std::string_view name) {
  for (const SchemeInfo& scheme : registry())
    if (scheme.name == name) return scheme;
  std::string known;
  for (const SchemeInfo& scheme : registry()) known += (known.empty() ? "" : ", ") + scheme.name;
  throw std::invalid_argument(fmt::format("unknown scheme '{}' (registered: {})", name, known));
}

bool registerScheme(SchemeInfo info) {
  auto& all = registry();
  // Sorted by name so every listing is the same whatever the static initialisation order.
  auto at = std::lower_bound(all.begin(), all.end(), info.name,
                             [](const SchemeInfo& s, const std::string& n) { return s.name < n; });
  all.insert(at, std::move(info));
  return true;
}

void checkLookupArguments(std::span<const Query> queries, int k, std::span<float> visibility) {
  if (!validFilterSize(k))
    throw std::invalid_argument("filter size must be odd and in [1, 17], got " + std::to_string(k));
  if (visibility.size() < queries.size())
    throw std::invalid_argument("lookup: fewer answer slots than queries");
}

}  // namespace sb

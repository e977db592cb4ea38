#include "schemes/interface/scheme.h"

#include "schemes/interface/lightspace.h"

#include <algorithm>

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

std::vector<SchemeInfo>& registry() {
  static std::vector<SchemeInfo> all;
  return all;
}

}  // namespace

ParamValues SchemeInfo::resolve(const Params& given) const {
  return ParamValues::resolve(name, params, given);
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

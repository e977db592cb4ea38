#include "harness/cell_key.h"

#include <algorithm>
#include <cstdint>

#include <fmt/format.h>

namespace sb {

namespace {

uint64_t fnv1a(std::string_view text) {
  uint64_t hash = 0xcbf29ce484222325ull;
  for (unsigned char c : text) hash = (hash ^ c) * 0x100000001b3ull;
  return hash;
}

}  // namespace

nlohmann::json recordRequest(const Record& r) {
  nlohmann::json request = {
      {"scene", r.scene.spec},   {"light_index", r.lightIndex}, {"mode", r.mode},
      {"scheme", r.scheme.name}, {"params", r.scheme.params},   {"resolution", r.resolution},
      {"tile_size", r.tileSize}};
  // A build in parts is its own request (its size may differ from the whole build's); whole
  // builds keep the keys they had before builds in parts existed.
  if (r.partSize) request["part_size"] = r.partSize;
  return request;
}

nlohmann::json recordIdentity(const Record& r) {
  nlohmann::json identity = recordRequest(r);
  identity["format"] = r.format;
  identity["scene_name"] = r.scene.name;
  identity["scene_hash"] = r.scene.hash;
  identity["light"] = r.light;
  return identity;
}

std::string fileNamePart(std::string_view text) {
  std::string part;
  bool unusual = false;  // lost more than case and ordinary punctuation: add a hash
  for (char c : text) {
    if (c >= 'A' && c <= 'Z') c = char(c - 'A' + 'a');
    if ((c >= 'a' && c <= 'z') || (c >= '0' && c <= '9') || c == '.') {
      part += c;
      continue;
    }
    unusual = unusual || std::string_view("-_:,= ").find(c) == std::string_view::npos;
    if (part.empty() || part.back() != '-') part += '-';
  }
  // A leading '.' would hide the file; edge dashes only make names harder to read.
  const size_t begin = part.find_first_not_of(".-");
  unusual = unusual || (begin != std::string::npos && part.find('.') < begin);
  part.erase(0, std::min(begin, part.size()));
  while (!part.empty() && part.back() == '-') part.pop_back();
  if (part.empty()) {
    part.push_back('x');
    unusual = unusual || !text.empty();
  }
  if (unusual) part += fmt::format("-{:08x}", uint32_t(fnv1a(text)));
  return part;
}

std::string readableCellKey(const Record& r) {
  std::string key = fileNamePart(r.scene.name);
  key += fmt::format("_{}_{}_{}", r.lightIndex, fileNamePart(r.mode), fileNamePart(r.scheme.name));
  for (const auto& [name, value] : r.scheme.params)  // sorted by name: a stable order
    key += fmt::format("_{}-{}", fileNamePart(name), fileNamePart(value));
  key += fmt::format("_{}", r.resolution);
  if (r.partSize) key += fmt::format("_parts-{}", r.partSize);

  // File names stop at 255 bytes; the request hash, ".json" and the temporary's prefix and
  // suffix are added to this.
  constexpr size_t kMaxKey = 190;
  if (key.size() > kMaxKey)
    key = fmt::format("{}-{:016x}", key.substr(0, kMaxKey - 17), fnv1a(key));
  return key;
}

std::string cellKey(const Record& r) {
  return fmt::format("{}_{:08x}", readableCellKey(r), uint32_t(fnv1a(recordRequest(r).dump())));
}

}  // namespace sb

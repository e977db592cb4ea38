#include "harness/part_file.h"

#include <algorithm>
#include <array>

#include <fmt/format.h>
#include <zstd.h>

#include "schemes/interface/atomic_file.h"

namespace sb {

namespace {

using Json = nlohmann::json;

Json costsJson(const PartCosts& costs) {
  Json phases = Json::array();
  for (const auto& [name, seconds] : costs.phases) phases.push_back({name, seconds});
  Json json{{"depth_seconds", costs.depthSeconds},
            {"wall_seconds", costs.wallSeconds},
            {"phases", phases},
            {"counters", costs.counters},
            {"peak_rss_bytes", costs.peakRssBytes},
            {"closed_fallbacks", costs.closedFallbacks},
            {"depth_shared_with", costs.depthSharedWith}};
  // Written only when shared, so that a file of an unshared part reads as it did before.
  if (!costs.encoderSharedWith.empty()) json["encoder_shared_with"] = costs.encoderSharedWith;
  if (costs.estimatedBytes) json["estimated_bytes"] = costs.estimatedBytes;
  return json;
}

// How a file holds its payload: a header key only where it is compressed (files written before
// compression have none), with the payload's size decompressed, which the merge's declared
// memory counts.
constexpr const char* kPayloadKey = "payload";
constexpr const char* kZstd = "zstd";
struct PayloadForm {
  bool compressed = false;
  uint64_t bytes = 0;  // decompressed
};
// zstd's fastest level: the MH's part payload of the open city's 4K² parts at 16K² 14.0 → 7.1 MB.
constexpr int kZstdLevel = 1;
// What a part payload can decompress to, at most: a bound against a crafted header's claim.
constexpr uint64_t kMaxPayloadBytes = uint64_t(1) << 40;

std::string headerJson(const PartIdentity& identity, const PartCosts& costs,
                       const PayloadForm& form) {
  Json json{{"structure", structureHeaderJson(identity.structure)},
            {"light", identity.light},
            {"tile", identity.tileSize},
            {"part_size", identity.partSize},
            {"part", identity.part},
            {"costs", costsJson(costs)}};
  if (form.compressed) json[kPayloadKey] = {{"compression", kZstd}, {"bytes", form.bytes}};
  return json.dump();
}

[[noreturn]] void headerError(std::string_view why) {
  throw FormatError(fmt::format("part header: {}", why));
}

const Json& field(const Json& object, const char* key) {
  if (!object.is_object() || !object.contains(key))
    headerError(fmt::format("missing key '{}'", key));
  return object.at(key);
}

template <class T>
T unsignedField(const Json& object, const char* key, uint64_t max) {
  const Json& value = field(object, key);
  if (!value.is_number_unsigned() || value.get<uint64_t>() > max)
    headerError(fmt::format("{} is not an unsigned integer up to {}", key, max));
  return T(value.get<uint64_t>());
}

double secondsField(const Json& object, const char* key) {
  const Json& value = field(object, key);
  if (!value.is_number() || !(value.get<double>() >= 0))
    headerError(fmt::format("{} is not a non-negative number", key));
  return value.get<double>();
}

std::vector<std::string> schemeNames(const Json& list, std::string_view key) {
  if (!list.is_array()) headerError(fmt::format("{} is not an array", key));
  std::vector<std::string> names;
  for (const Json& name : list) {
    if (!name.is_string()) headerError(fmt::format("{} holds a non-string", key));
    names.push_back(name.get<std::string>());
  }
  return names;
}

PartCosts parseCosts(const Json& json) {
  PartCosts costs;
  costs.depthSeconds = secondsField(json, "depth_seconds");
  costs.wallSeconds = secondsField(json, "wall_seconds");
  const Json& phases = field(json, "phases");
  if (!phases.is_array()) headerError("phases is not an array");
  for (const Json& phase : phases) {
    if (!phase.is_array() || phase.size() != 2 || !phase[0].is_string())
      headerError("a phase is not a [name, seconds] pair");
    const Json pair{{"seconds", phase[1]}};
    costs.phases.emplace_back(phase[0].get<std::string>(), secondsField(pair, "seconds"));
  }
  const Json& counters = field(json, "counters");
  if (!counters.is_object()) headerError("counters is not an object");
  for (const auto& item : counters.items())
    costs.counters[item.key()] = unsignedField<uint64_t>(counters, item.key().c_str(), UINT64_MAX);
  costs.peakRssBytes = unsignedField<uint64_t>(json, "peak_rss_bytes", UINT64_MAX);
  costs.closedFallbacks = unsignedField<uint64_t>(json, "closed_fallbacks", UINT64_MAX);
  costs.depthSharedWith = schemeNames(field(json, "depth_shared_with"), "depth_shared_with");
  if (json.contains("encoder_shared_with"))
    costs.encoderSharedWith = schemeNames(json.at("encoder_shared_with"), "encoder_shared_with");
  if (json.contains("estimated_bytes"))
    costs.estimatedBytes = unsignedField<uint64_t>(json, "estimated_bytes", UINT64_MAX);
  return costs;
}

struct PartHeader {
  PartIdentity identity;
  PartCosts costs;
  PayloadForm payload;
};

PayloadForm parsePayloadForm(const Json& json) {
  if (!json.is_object() || json.size() != 2 || field(json, "compression") != kZstd)
    headerError(fmt::format("payload {} is not {{\"compression\": \"{}\", \"bytes\": N}}",
                            json.dump(), kZstd));
  return {true, unsignedField<uint64_t>(json, "bytes", kMaxPayloadBytes)};
}

// Reads what headerJson writes: the structure header exactly as a structure file's, the rest
// checked for type and range.
PartHeader parseHeader(std::string_view text) {
  Json json;
  try {
    json = Json::parse(text);
  } catch (const Json::exception& error) {
    headerError(fmt::format("not JSON ({})", error.what()));
  }
  if (!json.is_object()) headerError("not an object");
  const bool compressed = json.contains(kPayloadKey);
  if (json.size() != 6u + compressed)
    headerError("not an object of the six part keys (and the payload's form)");
  PartIdentity identity;
  const Json& structure = field(json, "structure");
  if (!structure.is_string()) headerError("structure is not a string");
  identity.structure = parseStructureHeader(structure.get<std::string>());
  identity.light = field(json, "light");
  identity.tileSize = unsignedField<uint32_t>(json, "tile", UINT32_MAX);
  identity.partSize = unsignedField<uint32_t>(json, "part_size", UINT32_MAX);
  identity.part = unsignedField<uint64_t>(json, "part", UINT64_MAX);
  const uint32_t r = identity.structure.map.resolution;
  const auto powerOfTwo = [](uint32_t v) { return v != 0 && (v & (v - 1)) == 0; };
  if (!powerOfTwo(identity.partSize) || identity.partSize >= r)
    headerError(fmt::format("part_size {} is not a power of two below the resolution {}",
                            identity.partSize, r));
  if (!powerOfTwo(identity.tileSize) || identity.tileSize > identity.partSize)
    headerError(fmt::format("tile {} is not a power of two within the part size {}",
                            identity.tileSize, identity.partSize));
  const uint64_t perSide = r / identity.partSize;
  if (identity.part >= perSide * perSide)
    headerError(fmt::format("part {} does not exist in a map of {} parts", identity.part,
                            perSide * perSide));
  return {std::move(identity), parseCosts(field(json, "costs")),
          compressed ? parsePayloadForm(json.at(kPayloadKey)) : PayloadForm{}};
}

// The payload of `expected` bytes (the header's) in one zstd frame.
std::vector<uint8_t> decompressed(std::span<const uint8_t> frame, uint64_t expected) {
  const unsigned long long size = ZSTD_getFrameContentSize(frame.data(), frame.size());
  if (size == ZSTD_CONTENTSIZE_ERROR || size == ZSTD_CONTENTSIZE_UNKNOWN)
    throw FormatError("compressed payload: not a zstd frame that names its size");
  if (size != expected)
    throw FormatError(fmt::format(
        "compressed payload: a frame of {} bytes where the header says {}", size, expected));
  if (ZSTD_findFrameCompressedSize(frame.data(), frame.size()) != frame.size())
    throw FormatError("compressed payload: not one whole zstd frame");
  std::vector<uint8_t> bytes(size);
  const size_t got = ZSTD_decompress(bytes.data(), bytes.size(), frame.data(), frame.size());
  if (ZSTD_isError(got))
    throw FormatError(fmt::format("compressed payload: {}", ZSTD_getErrorName(got)));
  if (got != size)
    throw FormatError(
        fmt::format("compressed payload: {} bytes where its frame names {}", got, size));
  return bytes;
}

// The first field in which `found` is not the part `expected` describes.
void checkIdentity(const PartIdentity& found, const PartIdentity& expected) {
  const auto differ = [](const char* what, const auto& has, const auto& wanted) {
    throw PartMismatch(fmt::format("it belongs to another build: {} {} where this build has {}",
                                   what, has, wanted));
  };
  const StructureHeader &f = found.structure, &e = expected.structure;
  if (f.sceneHash != e.sceneHash) differ("scene hash", f.sceneHash, e.sceneHash);
  if (found.light != expected.light) differ("light", found.light.dump(), expected.light.dump());
  if (f.map.mode != e.map.mode) differ("mode", toString(f.map.mode), toString(e.map.mode));
  if (f.map.resolution != e.map.resolution)
    differ("resolution", f.map.resolution, e.map.resolution);
  if (found.partSize != expected.partSize) differ("part size", found.partSize, expected.partSize);
  if (found.tileSize != expected.tileSize) differ("tile size", found.tileSize, expected.tileSize);
  if (f.scheme != e.scheme) differ("scheme", f.scheme, e.scheme);
  if (f.params != e.params) {
    const auto text = [](const Params& params) {
      std::string joined;
      for (const auto& [name, value] : params)
        joined += fmt::format("{}{}={}", joined.empty() ? "" : " ", name, value);
      return joined;
    };
    differ("parameters", text(f.params), text(e.params));
  }
  if (found.part != expected.part) differ("part", found.part, expected.part);
}

}  // namespace

std::filesystem::path partFilePath(const std::filesystem::path& folder, uint64_t part) {
  return folder / fmt::format("part-{:06}.sbpart", part);
}

std::vector<uint8_t> encodePartFile(const PartIdentity& identity, const PartCosts& costs,
                                    std::span<const uint8_t> payload, bool compress) {
  ByteWriter tagged;
  putPayloadTag(tagged, identity.structure.scheme);
  if (compress) {
    std::vector<uint8_t> frame(ZSTD_compressBound(payload.size()));
    const size_t size =
        ZSTD_compress(frame.data(), frame.size(), payload.data(), payload.size(), kZstdLevel);
    if (ZSTD_isError(size))
      throw std::runtime_error(fmt::format("part file: zstd: {}", ZSTD_getErrorName(size)));
    tagged.append(frame.data(), size);
  } else {
    tagged.append(payload.data(), payload.size());
  }
  return frameFile(kPartFraming, headerJson(identity, costs, {compress, payload.size()}),
                   tagged.bytes());
}

PartFile decodePartFile(std::vector<uint8_t> bytes) {
  PartFile file;
  file.bytes = std::move(bytes);
  const FramedFile framed = unframeFile(kPartFraming, file.bytes);
  PartHeader header = parseHeader(framed.header);
  file.identity = std::move(header.identity), file.costs = std::move(header.costs);
  ByteReader tag(framed.payload);
  checkPayloadTag(tag, file.identity.structure.scheme);
  const size_t tagBytes = framed.payload.size() - tag.remaining();
  file.payload = framed.payload.subspan(tagBytes);
  if (header.payload.compressed) {
    file.bytes = decompressed(file.payload, header.payload.bytes);
    file.payload = file.bytes;
  }
  return file;
}

void savePartFile(const std::filesystem::path& path, const PartIdentity& identity,
                  const PartCosts& costs, std::span<const uint8_t> payload) {
  const std::vector<uint8_t> bytes = encodePartFile(identity, costs, payload);
  writeFileAtomically(path,
                      std::string_view(reinterpret_cast<const char*>(bytes.data()), bytes.size()));
}

uint64_t partPayloadBytes(const std::filesystem::path& path) {
  try {
    const PayloadForm form = parseHeader(readFramedHeader(kPartFraming, path)).payload;
    return form.compressed ? form.bytes : std::filesystem::file_size(path);
  } catch (const FormatError& error) {
    throw FormatError(fmt::format("part file '{}': {}", path.string(), error.what()));
  }
}

PartFile loadPartFile(const std::filesystem::path& path, const PartIdentity& expected) {
  try {
    std::vector<uint8_t> bytes = readFramedFile(kPartFraming, path, [&](std::string_view header) {
      checkIdentity(parseHeader(header).identity, expected);
    });
    PartFile file = decodePartFile(std::move(bytes));
    checkIdentity(file.identity, expected);
    return file;
  } catch (const FormatError& error) {
    throw FormatError(fmt::format("part file '{}': {}", path.string(), error.what()));
  } catch (const PartMismatch& error) {
    throw PartMismatch(fmt::format("part file '{}': {}", path.string(), error.what()));
  }
}

}  // namespace sb

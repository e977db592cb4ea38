#include "schemes/interface/serial.h"

#include <fstream>
#include <iterator>
#include <optional>

#include <fmt/format.h>
#include <xxhash.h>
#include <nlohmann/json.hpp>

#include "schemes/interface/atomic_file.h"
#include "schemes/interface/lightspace.h"

namespace sb {

namespace {

constexpr char kMagic[8] = {'S', 'H', 'D', 'W', 'B', 'N', 'C', 'H'};
// The largest header we accept: a scheme name and a handful of parameters.
constexpr uint32_t kMaxHeaderBytes = 1 << 16;

std::string headerJson(const StructureHeader& header) {
  nlohmann::json params = nlohmann::json::object();
  for (const auto& [name, value] : header.params) params[name] = value;
  return nlohmann::json{{"scheme", header.scheme},
                        {"params", params},
                        {"resolution", header.map.resolution},
                        {"depth_resolution", header.map.depthResolution},
                        {"mode", toString(header.map.mode)}}
      .dump();
}

StructureHeader parseHeader(std::string_view text) {
  StructureHeader header;
  try {
    const auto json = nlohmann::json::parse(text);
    header.scheme = json.at("scheme").get<std::string>();
    for (const auto& [name, value] : json.at("params").items())
      header.params[name] = value.get<std::string>();
    header.map.resolution = json.at("resolution").get<uint32_t>();
    header.map.depthResolution = json.at("depth_resolution").get<uint32_t>();
    header.map.mode = depthModeFromString(json.at("mode").get<std::string>());
  } catch (const std::exception& error) {
    throw FormatError(fmt::format("structure header is invalid: {}", error.what()));
  }
  const uint32_t r = header.map.resolution;
  if (!validResolution(r))
    throw FormatError(
        fmt::format("structure header: resolution {} is not a power of two in [8, 2^20]", r));
  return header;
}

}  // namespace

void ByteWriter::append(const void* data, size_t bytes) {
  const auto* begin = static_cast<const uint8_t*>(data);
  bytes_.insert(bytes_.end(), begin, begin + bytes);
}

const uint8_t* ByteReader::take(size_t bytes, const char* what) {
  if (bytes > remaining()) truncated(what);
  const uint8_t* at = bytes_.data() + offset_;
  offset_ += bytes;
  return at;
}

void ByteReader::truncated(const char* what) const {
  throw FormatError(
      fmt::format("truncated while reading {} (at byte {} of {})", what, offset_, bytes_.size()));
}

void ByteReader::mismatch(const char* what, uint64_t got, uint64_t expected) {
  throw FormatError(
      fmt::format("{}: {} elements where the header implies {}", what, got, expected));
}

void ByteReader::expectEnd() const {
  if (remaining() != 0)
    throw FormatError(fmt::format("{} unexpected bytes after the payload", remaining()));
}

std::vector<uint8_t> encodeStructureFile(const StructureHeader& header, const Decoder& decoder) {
  ByteWriter payload;
  decoder.save(payload);
  const std::string json = headerJson(header);
  ByteWriter file;
  file.append(kMagic, sizeof kMagic);
  file.put<uint32_t>(kStructureFileVersion);
  file.put<uint32_t>(uint32_t(json.size()));
  file.append(json.data(), json.size());
  file.put<uint64_t>(payload.bytes().size());
  file.append(payload.bytes().data(), payload.bytes().size());
  file.put<uint64_t>(XXH3_64bits(file.bytes().data(), file.bytes().size()));
  return file.release();
}

std::unique_ptr<Decoder> decodeStructureFile(std::span<const uint8_t> file,
                                             StructureHeader* headerOut) {
  constexpr size_t kMinimum = sizeof kMagic + 4 + 4 + 8 + 8;
  if (file.size() < kMinimum)
    throw FormatError(
        fmt::format("not a shadowbench structure: {} bytes is shorter than any", file.size()));
  if (std::memcmp(file.data(), kMagic, sizeof kMagic) != 0)
    throw FormatError("not a shadowbench structure (bad magic)");
  ByteReader reader(file.subspan(sizeof kMagic));
  const auto version = reader.get<uint32_t>("container version");
  if (version != kStructureFileVersion)
    throw FormatError(
        fmt::format("structure file version {} is not supported (this build reads {})", version,
                    kStructureFileVersion));
  const size_t body = file.size() - sizeof(uint64_t);
  uint64_t stored;
  std::memcpy(&stored, file.data() + body, sizeof stored);
  if (XXH3_64bits(file.data(), body) != stored)
    throw FormatError("structure file is truncated or corrupted (checksum mismatch)");

  const auto headerBytes = reader.get<uint32_t>("header length");
  if (headerBytes > kMaxHeaderBytes || headerBytes > reader.remaining())
    throw FormatError(fmt::format("structure header length {} is invalid", headerBytes));
  std::string json(headerBytes, '\0');
  for (char& c : json) c = char(reader.get<uint8_t>("header"));
  StructureHeader header = parseHeader(json);
  const auto payloadBytes = reader.get<uint64_t>("payload length");
  if (reader.remaining() < sizeof(uint64_t) ||
      payloadBytes != reader.remaining() - sizeof(uint64_t))
    throw FormatError(fmt::format("payload length {} does not match the file ({} bytes left)",
                                  payloadBytes, reader.remaining() - sizeof(uint64_t)));

  const SchemeInfo* scheme = nullptr;
  std::optional<ParamValues> params;
  try {
    scheme = &findScheme(header.scheme);
    params = scheme->resolve(header.params);
    header.params = params->text();
  } catch (const std::invalid_argument& error) {
    throw FormatError(fmt::format("structure header: {}", error.what()));
  }
  const size_t payloadStart = file.size() - sizeof(uint64_t) - payloadBytes;
  ByteReader payload(file.subspan(payloadStart, payloadBytes));
  auto decoder = scheme->load(payload, header.map, *params);
  payload.expectEnd();
  if (headerOut) *headerOut = std::move(header);
  return decoder;
}

void saveStructure(const std::filesystem::path& path, const StructureHeader& header,
                   const Decoder& decoder) {
  const std::vector<uint8_t> bytes = encodeStructureFile(header, decoder);
  writeFileAtomically(path,
                      std::string_view(reinterpret_cast<const char*>(bytes.data()), bytes.size()));
}

std::unique_ptr<Decoder> loadStructure(const std::filesystem::path& path, StructureHeader* header) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw FormatError(fmt::format("cannot open structure file '{}'", path.string()));
  std::vector<uint8_t> bytes((std::istreambuf_iterator<char>(in)),
                             std::istreambuf_iterator<char>());
  try {
    return decodeStructureFile(bytes, header);
  } catch (const FormatError& error) {
    throw FormatError(fmt::format("structure file '{}': {}", path.string(), error.what()));
  }
}

}  // namespace sb

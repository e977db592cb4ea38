#include "schemes/interface/serial.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <cerrno>
#include <cstring>

#include <fmt/format.h>
#include <xxhash.h>
#include <nlohmann/json.hpp>

#include "schemes/interface/atomic_file.h"
#include "schemes/interface/lightspace.h"

namespace sb {

namespace {

// Magic, container version and header length: what a reader checks before anything else.
constexpr size_t kPrefixBytes = sizeof(FileFraming::magic) + 2 * sizeof(uint32_t);
// Everything but the header and the payload: the prefix, the payload length and the checksum.
constexpr size_t kFramingBytes = kPrefixBytes + 2 * sizeof(uint64_t);
// The largest header we accept: a scheme name, a handful of parameters, a part's build figures.
constexpr uint32_t kMaxHeaderBytes = 1 << 16;
constexpr size_t kSceneHashDigits = 16;

using Json = nlohmann::json;

bool validSceneHash(std::string_view hash) {
  return hash.empty() || (hash.size() == kSceneHashDigits &&
                          hash.find_first_not_of("0123456789abcdef") == std::string_view::npos);
}

}  // namespace

std::string structureHeaderJson(const StructureHeader& header) {
  Json params = Json::object();
  for (const auto& [name, value] : header.params) params[name] = value;
  return Json{{"scheme", header.scheme},
              {"params", params},
              {"resolution", header.map.resolution},
              {"depth_resolution", header.map.depthResolution},
              {"mode", toString(header.map.mode)},
              {"scene_hash", header.sceneHash}}
      .dump();
}

namespace {

[[noreturn]] void headerError(std::string_view why) {
  throw FormatError(fmt::format("structure header: {}", why));
}

// A crafted header may hold anything: errors show at most the first 80 characters of a value.
std::string shown(std::string_view text) {
  constexpr size_t kShown = 80;
  return text.size() <= kShown ? std::string(text) : std::string(text.substr(0, kShown)) + "...";
}

uint32_t headerUint32(const Json& header, const char* key) {
  const Json& value = header.at(key);
  if (!value.is_number_unsigned() || value.get<uint64_t>() > UINT32_MAX)
    headerError(fmt::format("{} {} is not an unsigned 32-bit integer", key, shown(value.dump())));
  return uint32_t(value.get<uint64_t>());
}

std::string headerString(const Json& header, const char* key) {
  const Json& value = header.at(key);
  if (!value.is_string())
    headerError(fmt::format("{} {} is not a string", key, shown(value.dump())));
  return value.get<std::string>();
}

struct ParsedHeader {
  StructureHeader header;  // parameters resolved
  const SchemeInfo* scheme = nullptr;
  ParamValues params;
};

// Accepts exactly what headerJson writes for a registered scheme: every key once and no other,
// integers in range without sign or fraction, strings where it writes strings, parameters the
// scheme's registry row accepts, and the same bytes headerJson would give.
ParsedHeader parseHeader(std::string_view text) {
  Json json;
  try {
    json = Json::parse(text);
  } catch (const Json::exception& error) {
    headerError(fmt::format("not JSON ({})", error.what()));
  }
  if (!json.is_object()) headerError("not a JSON object");
  constexpr std::array<const char*, 6> kKeys = {"depth_resolution", "mode",       "params",
                                                "resolution",       "scene_hash", "scheme"};
  for (const auto& item : json.items())
    if (std::find(kKeys.begin(), kKeys.end(), item.key()) == kKeys.end())
      headerError(fmt::format("unknown key '{}'", shown(item.key())));
  for (const char* key : kKeys)
    if (!json.contains(key)) headerError(fmt::format("missing key '{}'", key));

  ParsedHeader parsed;
  StructureHeader& header = parsed.header;
  header.scheme = headerString(json, "scheme");
  const Json& params = json.at("params");
  if (!params.is_object())
    headerError(fmt::format("params {} is not an object", shown(params.dump())));
  for (const auto& item : params.items()) {
    if (!item.value().is_string())
      headerError(fmt::format("parameter '{}' is {}, not a string", shown(item.key()),
                              shown(item.value().dump())));
    header.params[item.key()] = item.value().get<std::string>();
  }
  header.map.resolution = headerUint32(json, "resolution");
  if (!validResolution(header.map.resolution))
    headerError(
        fmt::format("resolution {} is not a power of two in [8, 2^20]", header.map.resolution));
  header.map.depthResolution = headerUint32(json, "depth_resolution");
  header.sceneHash = headerString(json, "scene_hash");
  if (!validSceneHash(header.sceneHash))
    headerError(fmt::format("scene_hash '{}' is not {} lowercase hex digits",
                            shown(header.sceneHash), kSceneHashDigits));
  try {
    header.map.mode = depthModeFromString(headerString(json, "mode"));
    parsed.scheme = &findScheme(header.scheme);
    parsed.params = parsed.scheme->resolve(header.params);
    header.params = parsed.params.text();
  } catch (const std::invalid_argument& error) {
    headerError(error.what());
  }
  // The writer gives depth schemes no slices and voxel schemes R of them (DESIGN §4).
  const uint32_t slices = parsed.scheme->kind == SchemeKind::Voxel ? header.map.resolution : 0;
  if (header.map.depthResolution != slices)
    headerError(fmt::format("depth_resolution {} where the {} scheme '{}' at resolution {} has {}",
                            header.map.depthResolution, toString(parsed.scheme->kind),
                            header.scheme, header.map.resolution, slices));
  if (json.dump() != text)
    headerError(
        "not written as this version writes it (spacing, key order, escapes or a "
        "repeated key)");
  return parsed;
}

// Magic, version and header length, from the first kPrefixBytes of a file.
uint32_t headerLengthFromPrefix(const FileFraming& framing, std::span<const uint8_t> prefix) {
  if (std::memcmp(prefix.data(), framing.magic.data(), framing.magic.size()) != 0)
    throw FormatError(fmt::format("not a shadowbench {} (bad magic)", framing.noun));
  ByteReader reader(prefix.subspan(framing.magic.size()));
  const auto version = reader.get<uint32_t>("container version");
  if (version != framing.version)
    throw FormatError(fmt::format("{} version {} is not supported (this build reads {})",
                                  framing.noun, version, framing.version));
  const auto headerBytes = reader.get<uint32_t>("header length");
  if (headerBytes > kMaxHeaderBytes)
    throw FormatError(fmt::format("{} header length {} is invalid", framing.noun, headerBytes));
  return headerBytes;
}

void checkFileSize(const FileFraming& framing, uint64_t fileBytes) {
  if (fileBytes < kFramingBytes)
    throw FormatError(
        fmt::format("not a shadowbench {}: {} bytes is shorter than any", framing.noun, fileBytes));
}

void checkHeaderFits(const FileFraming& framing, uint32_t headerBytes, uint64_t fileBytes) {
  if (headerBytes > fileBytes - kFramingBytes)
    throw FormatError(
        fmt::format("{} is truncated or corrupted: a header of {} bytes does not fit {} bytes",
                    framing.noun, headerBytes, fileBytes));
}

// The payload length stored after the header must account for every other byte of the file.
void checkPayloadLength(const FileFraming& framing, uint64_t payloadBytes, uint32_t headerBytes,
                        uint64_t fileBytes) {
  const uint64_t left = fileBytes - kFramingBytes - headerBytes;
  if (payloadBytes != left)
    throw FormatError(
        fmt::format("{} is truncated or corrupted: payload length {} where the file holds {}",
                    framing.noun, payloadBytes, left));
}

uint64_t loadU64(const uint8_t* bytes) {
  uint64_t value;
  std::memcpy(&value, bytes, sizeof value);
  return value;
}

// A structure file opened for reading: regular files only (a device or a FIFO has no size to
// check a header against, and /dev/zero never ends).
class StructureFileReader {
 public:
  explicit StructureFileReader(const std::filesystem::path& path)
      : fd_(::open(path.c_str(), O_RDONLY | O_CLOEXEC | O_NONBLOCK)) {
    if (fd_ < 0) throw FormatError(fmt::format("cannot open: {}", std::strerror(errno)));
    struct stat status;
    if (::fstat(fd_, &status) != 0) {
      const int error = errno;
      ::close(fd_);
      throw FormatError(fmt::format("cannot read: {}", std::strerror(error)));
    }
    if (!S_ISREG(status.st_mode)) {
      ::close(fd_);
      throw FormatError("not a regular file");
    }
    size_ = uint64_t(status.st_size);
  }
  ~StructureFileReader() { ::close(fd_); }
  StructureFileReader(const StructureFileReader&) = delete;
  StructureFileReader& operator=(const StructureFileReader&) = delete;

  uint64_t size() const { return size_; }

  // Exactly into.size() bytes from `offset`; a file that shrank since it was opened is truncated.
  void read(uint64_t offset, std::span<uint8_t> into) const {
    while (!into.empty()) {
      const ssize_t got = ::pread(fd_, into.data(), into.size(), off_t(offset));
      if (got < 0 && errno == EINTR) continue;
      if (got < 0) throw FormatError(fmt::format("cannot read: {}", std::strerror(errno)));
      if (got == 0) throw FormatError(fmt::format("truncated at byte {} while reading", offset));
      offset += uint64_t(got);
      into = into.subspan(size_t(got));
    }
  }

 private:
  int fd_;
  uint64_t size_ = 0;
};

}  // namespace

StructureHeader parseStructureHeader(std::string_view json, ParamValues* params) {
  ParsedHeader parsed = parseHeader(json);
  if (params) *params = std::move(parsed.params);
  return std::move(parsed.header);
}

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

std::vector<uint8_t> frameFile(const FileFraming& framing, std::string_view header,
                               std::span<const uint8_t> payload) {
  ByteWriter file;
  file.append(framing.magic.data(), framing.magic.size());
  file.put<uint32_t>(framing.version);
  file.put<uint32_t>(uint32_t(header.size()));
  file.append(header.data(), header.size());
  file.put<uint64_t>(payload.size());
  file.append(payload.data(), payload.size());
  file.put<uint64_t>(XXH3_64bits(file.bytes().data(), file.bytes().size()));
  return file.release();
}

FramedFile unframeFile(const FileFraming& framing, std::span<const uint8_t> file) {
  checkFileSize(framing, file.size());
  const uint32_t headerBytes = headerLengthFromPrefix(framing, file.first(kPrefixBytes));
  const size_t body = file.size() - sizeof(uint64_t);
  if (XXH3_64bits(file.data(), body) != loadU64(file.data() + body))
    throw FormatError(
        fmt::format("{} is truncated or corrupted (checksum mismatch)", framing.noun));
  checkHeaderFits(framing, headerBytes, file.size());
  const size_t payloadLengthAt = kPrefixBytes + headerBytes;
  const uint64_t payloadBytes = loadU64(file.data() + payloadLengthAt);
  checkPayloadLength(framing, payloadBytes, headerBytes, file.size());
  return {std::string_view(reinterpret_cast<const char*>(file.data()) + kPrefixBytes, headerBytes),
          file.subspan(payloadLengthAt + sizeof(uint64_t), payloadBytes)};
}

namespace {

std::string headerOf(const FileFraming& framing, const StructureFileReader& file) {
  checkFileSize(framing, file.size());
  std::array<uint8_t, kPrefixBytes> prefix;
  file.read(0, prefix);
  const uint32_t headerBytes = headerLengthFromPrefix(framing, prefix);
  checkHeaderFits(framing, headerBytes, file.size());
  std::string header(headerBytes, '\0');
  file.read(kPrefixBytes, std::span(reinterpret_cast<uint8_t*>(header.data()), header.size()));
  return header;
}

}  // namespace

std::string readFramedHeader(const FileFraming& framing, const std::filesystem::path& path) {
  return headerOf(framing, StructureFileReader(path));
}

std::vector<uint8_t> readFramedFile(const FileFraming& framing, const std::filesystem::path& path,
                                    const std::function<void(std::string_view)>& checkHeader) {
  const StructureFileReader file(path);
  const std::string header = headerOf(framing, file);
  const uint32_t headerBytes = uint32_t(header.size());
  checkHeader(header);
  uint64_t payloadBytes;
  file.read(kPrefixBytes + headerBytes,
            std::span(reinterpret_cast<uint8_t*>(&payloadBytes), sizeof payloadBytes));
  checkPayloadLength(framing, payloadBytes, headerBytes, file.size());
  // Only now is the file's size known to be the framing's: read it whole.
  std::vector<uint8_t> bytes(file.size());
  file.read(0, bytes);
  return bytes;
}

void putPayloadTag(ByteWriter& out, std::string_view scheme) {
  if (scheme.empty() || scheme.size() > UINT8_MAX)
    throw std::invalid_argument(
        fmt::format("scheme name '{}' cannot tag a payload", shown(scheme)));
  out.put<uint8_t>(uint8_t(scheme.size()));
  out.append(scheme.data(), scheme.size());
}

void checkPayloadTag(ByteReader& in, std::string_view scheme) {
  const auto length = in.get<uint8_t>("payload tag length");
  std::string tag(length, '\0');
  for (char& c : tag) c = char(in.get<uint8_t>("payload tag"));
  if (tag != scheme)
    throw FormatError(
        fmt::format("the payload was written by scheme '{}', not by '{}' as the header says",
                    shown(tag), scheme));
}

std::vector<uint8_t> encodeStructureFile(const StructureHeader& header, const Decoder& decoder) {
  if (!validSceneHash(header.sceneHash))
    throw std::invalid_argument(fmt::format("scene hash '{}' is not {} lowercase hex digits",
                                            shown(header.sceneHash), kSceneHashDigits));
  ByteWriter payload;
  putPayloadTag(payload, header.scheme);
  decoder.save(payload);
  return frameFile(kStructureFraming, structureHeaderJson(header), payload.bytes());
}

std::unique_ptr<Decoder> decodeStructureFile(std::span<const uint8_t> file,
                                             StructureHeader* headerOut) {
  const FramedFile framed = unframeFile(kStructureFraming, file);
  ParsedHeader parsed = parseHeader(framed.header);
  ByteReader payload(framed.payload);
  checkPayloadTag(payload, parsed.header.scheme);
  auto decoder = parsed.scheme->load(payload, parsed.header.map, parsed.params);
  payload.expectEnd();
  if (headerOut) *headerOut = std::move(parsed.header);
  return decoder;
}

void saveStructure(const std::filesystem::path& path, const StructureHeader& header,
                   const Decoder& decoder) {
  const std::vector<uint8_t> bytes = encodeStructureFile(header, decoder);
  writeFileAtomically(path,
                      std::string_view(reinterpret_cast<const char*>(bytes.data()), bytes.size()));
}

std::unique_ptr<Decoder> loadStructure(const std::filesystem::path& path, StructureHeader* header) {
  try {
    // A foreign or crafted header is refused before the payload is read.
    const std::vector<uint8_t> bytes =
        readFramedFile(kStructureFraming, path, [](std::string_view json) { parseHeader(json); });
    return decodeStructureFile(bytes, header);
  } catch (const FormatError& error) {
    throw FormatError(fmt::format("structure file '{}': {}", path.string(), error.what()));
  }
}

}  // namespace sb

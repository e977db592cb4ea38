// Serialisation shared by every scheme: little-endian byte buffers with bounds-checked reads,
// and the structure file that wraps a scheme's payload (versioned, checksummed).
#pragma once

#include <array>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <functional>
#include <memory>
#include <span>
#include <stdexcept>
#include <string>
#include <string_view>
#include <type_traits>
#include <vector>

#include "schemes/interface/scheme.h"

namespace sb {

// A structure file that is truncated, corrupted, of another version or otherwise invalid.
class FormatError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

class ByteWriter {
 public:
  template <class T>
  void put(const T& value) {
    static_assert(std::is_trivially_copyable_v<T>);
    append(&value, sizeof(T));
  }
  template <class T>
  void putArray(std::span<const T> values) {
    static_assert(std::is_trivially_copyable_v<T>);
    put<uint64_t>(values.size());
    append(values.data(), values.size_bytes());
  }
  void append(const void* data, size_t bytes);
  const std::vector<uint8_t>& bytes() const { return bytes_; }
  std::vector<uint8_t> release() { return std::move(bytes_); }

 private:
  std::vector<uint8_t> bytes_;
};

// Reads what a ByteWriter wrote; every read is checked against the end and names `what` in
// the FormatError it throws.
class ByteReader {
 public:
  explicit ByteReader(std::span<const uint8_t> bytes) : bytes_(bytes) {}
  template <class T>
  T get(const char* what) {
    static_assert(std::is_trivially_copyable_v<T>);
    T value;
    std::memcpy(&value, take(sizeof(T), what), sizeof(T));
    return value;
  }
  // An array written by putArray; `expected` (when not ~0) is the element count the caller
  // derived from the header, and any other count is an error.
  template <class T>
  std::vector<T> getArray(const char* what, uint64_t expected = ~uint64_t(0)) {
    static_assert(std::is_trivially_copyable_v<T>);
    const uint64_t count = get<uint64_t>(what);
    if (expected != ~uint64_t(0) && count != expected) mismatch(what, count, expected);
    if (count > remaining() / sizeof(T)) truncated(what);
    std::vector<T> values(count);
    const uint8_t* bytes = take(count * sizeof(T), what);
    if (count != 0) std::memcpy(values.data(), bytes, count * sizeof(T));  // data() may be null
    return values;
  }
  size_t remaining() const { return bytes_.size() - offset_; }
  // Passes over `bytes` bytes unread (FormatError naming `what` where fewer remain).
  void skip(size_t bytes, const char* what) { take(bytes, what); }
  // Throws unless every byte was consumed: trailing bytes mean a corrupted or foreign file.
  void expectEnd() const;

 private:
  const uint8_t* take(size_t bytes, const char* what);
  [[noreturn]] void truncated(const char* what) const;
  [[noreturn]] static void mismatch(const char* what, uint64_t got, uint64_t expected);

  std::span<const uint8_t> bytes_;
  size_t offset_ = 0;
};

// The header every structure file carries before the scheme's payload.
struct StructureHeader {
  std::string scheme;
  Params params;
  MapInfo map;
  // Scene::hash() of the scene the structure was built from (16 lowercase hex digits), or ""
  // for a structure built from no scene (a synthetic map in a test).
  std::string sceneHash;
};

// The framing every shadowbench file shares (structure files, part files), all little-endian:
//   8 bytes  magic
//   u32      container version
//   u32      header length H, then H bytes of JSON
//   u64      payload length P, then P bytes of payload
//   u64      XXH3-64 of every byte before it
struct FileFraming {
  std::array<char, 8> magic;
  uint32_t version;
  std::string_view noun;  // "structure file", "part file": what error messages call it
};

std::vector<uint8_t> frameFile(const FileFraming& framing, std::string_view header,
                               std::span<const uint8_t> payload);
// The header and payload of a framed file, after magic, version, lengths and checksum are checked.
// Throws FormatError.
struct FramedFile {
  std::string_view header;
  std::span<const uint8_t> payload;
};
FramedFile unframeFile(const FileFraming& framing, std::span<const uint8_t> file);
// A framed file's bytes from disk: regular files only; `checkHeader` sees the header before the
// payload is read, so a foreign file is refused without reading it whole. Throws FormatError.
std::vector<uint8_t> readFramedFile(const FileFraming& framing, const std::filesystem::path& path,
                                    const std::function<void(std::string_view)>& checkHeader);
// A framed file's header alone, its payload not read (its framing's checks that need only the
// prefix and the file's size made). Throws FormatError.
std::string readFramedHeader(const FileFraming& framing, const std::filesystem::path& path);

// The payload tag (u8 length n, then the n bytes of the writing scheme's name) makes a payload
// self-identifying: formats that two schemes share (mh and mmh) cannot be swapped under each
// other's header.
void putPayloadTag(ByteWriter& out, std::string_view scheme);
void checkPayloadTag(ByteReader& in, std::string_view scheme);  // throws FormatError

// A structure file is framed with magic "SHDWBNCH" and kStructureFileVersion; its header is JSON
// exactly as structureHeaderJson dumps it: the keys depth_resolution, mode, params (an object of
// strings), resolution, scene_hash, scheme; its payload is the payload tag, then the scheme's.
inline constexpr uint32_t kStructureFileVersion = 2;
inline constexpr FileFraming kStructureFraming{
    {'S', 'H', 'D', 'W', 'B', 'N', 'C', 'H'}, kStructureFileVersion, "structure file"};

std::string structureHeaderJson(const StructureHeader& header);
// Accepts exactly what structureHeaderJson writes for a registered scheme, its parameters
// resolved against the scheme's row (into `params` when given). Throws FormatError.
StructureHeader parseStructureHeader(std::string_view json, ParamValues* params = nullptr);

// Throws std::invalid_argument for a header the reader would refuse (an invalid scene hash).
std::vector<uint8_t> encodeStructureFile(const StructureHeader& header, const Decoder& decoder);
// Validates magic, version, checksum, header (every value exactly as a writer writes it, the
// parameters against the scheme's registry row) and payload tag, then has the scheme validate
// its payload. Throws FormatError.
std::unique_ptr<Decoder> decodeStructureFile(std::span<const uint8_t> file,
                                             StructureHeader* header);

// File versions of the two above; `save` writes atomically (temporary file, then rename).
// `load` refuses anything but a regular file, and reads the payload only after the fixed-size
// prefix, the header and the payload length agree with the file's size.
void saveStructure(const std::filesystem::path& path, const StructureHeader& header,
                   const Decoder& decoder);
std::unique_ptr<Decoder> loadStructure(const std::filesystem::path& path, StructureHeader* header);

}  // namespace sb

#include "scenes/model_header.h"

#include <algorithm>
#include <cctype>
#include <charconv>
#include <fstream>
#include <string_view>
#include <vector>

#include <fmt/format.h>

namespace sb::detail {
namespace {

namespace fs = std::filesystem;

// What Assimp allocates at least per declared element: a vertex position (aiVector3D) and an
// aiFace, and what our Mesh keeps: a position and a triangle.
constexpr uint64_t kBytesPerVertex = 12 + 12;
constexpr uint64_t kBytesPerFace = 16 + 12;

// The first `limit` bytes of the file: enough for any header.
std::string head(const fs::path& path, size_t limit) {
  std::ifstream in(path, std::ios::binary);
  std::string text(limit, '\0');
  in.read(text.data(), static_cast<std::streamsize>(limit));
  text.resize(static_cast<size_t>(std::max<std::streamsize>(in.gcount(), 0)));
  return text;
}

std::optional<uint64_t> parseCount(std::string_view text) {
  uint64_t value = 0;
  const auto [end, error] = std::from_chars(text.data(), text.data() + text.size(), value);
  if (error != std::errc{} || end != text.data() + text.size()) return std::nullopt;
  return value;
}

// Whitespace-separated words of a line.
std::vector<std::string_view> words(std::string_view line) {
  std::vector<std::string_view> result;
  size_t at = 0;
  while (true) {
    at = line.find_first_not_of(" \t\r", at);
    if (at == std::string_view::npos) return result;
    const size_t end = std::min(line.find_first_of(" \t\r", at), line.size());
    result.push_back(line.substr(at, end - at));
    at = end;
  }
}

std::string lowerExtension(const fs::path& path) {
  std::string ext = path.extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(),
                 [](unsigned char c) { return std::tolower(c); });
  return ext;
}

struct Element {
  std::string name;
  uint64_t count = 0;
  uint64_t minItemBytes = 0;  // the smallest encoding of one item in the file
};

// Refuses the file when its elements need more than the `available` bytes after the header.
void checkElementsFit(const std::vector<Element>& elements, uint64_t available, uint64_t fileSize,
                      const std::string& prefix) {
  unsigned __int128 needed = 0;  // up to 2⁶⁴ elements of a few bytes each
  std::vector<std::string> declared;
  for (const Element& e : elements) {
    needed += static_cast<unsigned __int128>(e.count) * e.minItemBytes;
    declared.push_back(fmt::format("{} {}", e.count, e.name));
  }
  if (needed > available)
    throw SceneError(
        fmt::format("{}: the header declares {} elements, which need at least {} bytes, but the "
                    "file is only {} bytes long",
                    prefix, fmt::join(declared, " and "), needed, fileSize));
}

SceneFootprint footprintOf(uint64_t vertices, uint64_t faces) {
  return {vertices, faces, vertices * kBytesPerVertex + faces * kBytesPerFace};
}

// PLY (Turk 1994): "ply", "format ascii|binary_little_endian|binary_big_endian 1.0", then
// "element <name> <count>" each followed by its "property <type> <name>" or "property list
// <count type> <index type> <name>" lines, "comment" and "obj_info" lines anywhere, up to
// "end_header". Anything else is refused here: Assimp 5.2's PLY reader hangs on a header without
// "end_header" and crashes on a malformed "format" line (found by fuzzing, fuzz/regressions/).
SceneFootprint plyFootprint(const fs::path& path, uint64_t fileSize, const std::string& prefix) {
  constexpr size_t kMaxHeader = 1 << 16;
  const std::string text = head(path, kMaxHeader);
  const auto refuse = [&](const std::string& why) -> SceneFootprint {
    throw SceneError(fmt::format("{}: not a PLY file this reader accepts: {}", prefix, why));
  };
  auto typeBytes = [](std::string_view type) -> uint64_t {
    for (std::string_view t : {"char", "uchar", "int8", "uint8"})
      if (type == t) return 1;
    for (std::string_view t : {"short", "ushort", "int16", "uint16"})
      if (type == t) return 2;
    for (std::string_view t : {"int", "uint", "int32", "uint32", "float", "float32"})
      if (type == t) return 4;
    for (std::string_view t : {"double", "float64"})
      if (type == t) return 8;
    return 0;
  };
  bool ascii = false, formatSeen = false;
  std::vector<Element> elements;
  size_t body = std::string::npos;  // the first byte after the header
  for (size_t at = 0, number = 1; at < text.size(); ++number) {
    const size_t newline = text.find('\n', at);
    if (newline == std::string::npos) break;
    const std::vector<std::string_view> w = words(std::string_view(text).substr(at, newline - at));
    at = newline + 1;
    const std::string where = fmt::format("header line {}", number);
    if (number == 1) {
      if (w.size() != 1 || w[0] != "ply") refuse("the first line is not 'ply'");
      continue;
    }
    if (w.empty()) refuse(where + " is empty");
    if (w[0] == "end_header" && w.size() == 1) {
      body = at;
      break;
    }
    if (w[0] == "comment" || w[0] == "obj_info") continue;
    if (w[0] == "format") {
      if (formatSeen || w.size() != 3 || w[2] != "1.0" ||
          (w[1] != "ascii" && w[1] != "binary_little_endian" && w[1] != "binary_big_endian"))
        refuse(where +
               ": the format must be given once, as ascii, binary_little_endian or "
               "binary_big_endian 1.0");
      formatSeen = true;
      ascii = w[1] == "ascii";
    } else if (w[0] == "element" && w.size() == 3) {
      const std::optional<uint64_t> count = parseCount(w[2]);
      if (!count) refuse(where + ": the element count is not a number");
      elements.push_back({std::string(w[1]), *count, 0});
    } else if (w[0] == "property" && !elements.empty()) {
      // A list may be empty: its smallest encoding is its count alone. In ASCII every value
      // takes at least a digit and a separator.
      const bool list = w.size() == 5 && w[1] == "list";
      if (!list && w.size() != 3) refuse(where + ": a property is 'property <type> <name>'");
      const uint64_t bytes = typeBytes(w[1 + list]);
      const uint64_t itemBytes = list ? typeBytes(w[3]) : bytes;
      if (bytes == 0 || itemBytes == 0) refuse(where + ": unknown property type");
      if (list && (w[2].find("float") != std::string_view::npos || w[2] == "double"))
        refuse(where + ": a list's length must be an integer type");
      elements.back().minItemBytes += ascii ? 2 : bytes;
    } else {
      refuse(where + " is not a format, element, property or comment line");
    }
  }
  if (body == std::string::npos)
    refuse(fmt::format("no 'end_header' line in its first {} bytes", kMaxHeader));
  if (!formatSeen) refuse("no 'format' line");
  uint64_t afterHeader = fileSize - std::min<uint64_t>(body, fileSize);
  if (ascii) ++afterHeader;  // the last value needs no separator
  checkElementsFit(elements, afterHeader, fileSize, prefix);
  uint64_t vertices = 0, faces = 0;
  for (const Element& e : elements) {
    if (e.name == "vertex") vertices = e.count;
    if (e.name == "face") faces = e.count;
  }
  return footprintOf(vertices, faces);
}

// OFF: a keyword ending in "OFF" (OFF, COFF, NOFF, …), then "<vertices> <faces> <edges>", in
// ASCII, '#' comments allowed; a vertex line holds at least three numbers ("0 0 0\n"), a face
// line at least its corner count ("0\n").
std::optional<SceneFootprint> offFootprint(const fs::path& path, uint64_t fileSize,
                                           const std::string& prefix) {
  const std::string text = head(path, 1 << 16);
  std::vector<std::string_view> tokens;
  size_t at = 0;
  while (tokens.size() < 3 && at < text.size()) {
    const size_t lineEnd = std::min(text.find('\n', at), text.size());
    std::string_view line = std::string_view(text).substr(at, lineEnd - at);
    at = lineEnd + 1;
    line = line.substr(0, line.find('#'));
    for (std::string_view w : words(line)) tokens.push_back(w);
  }
  // "nOFF" puts the dimension before the counts; "OFF BINARY" is another layout.
  if (tokens.size() < 3 || !tokens[0].ends_with("OFF") ||
      tokens[0].find('n') != std::string_view::npos || tokens[1] == "BINARY")
    return std::nullopt;
  const std::optional<uint64_t> vertices = parseCount(tokens[1]), faces = parseCount(tokens[2]);
  if (!vertices || !faces) return std::nullopt;
  const uint64_t afterHeader = fileSize - std::min<uint64_t>(at, fileSize) + 1;
  checkElementsFit({{"vertex", *vertices, 6}, {"face", *faces, 2}}, afterHeader, fileSize, prefix);
  return footprintOf(*vertices, *faces);
}

// Binary STL: an 80-byte header, a little-endian uint32 triangle count and 50 bytes per
// triangle. An ASCII STL begins with "solid" and declares no count.
std::optional<SceneFootprint> stlFootprint(const fs::path& path, uint64_t fileSize,
                                           const std::string& prefix) {
  const std::string text = head(path, 84);
  const size_t first = text.find_first_not_of(" \t\r\n");
  if (text.size() < 84 || (first != std::string::npos && text.compare(first, 5, "solid") == 0))
    return std::nullopt;
  uint64_t triangles = 0;
  for (int i = 3; i >= 0; --i) triangles = triangles << 8 | static_cast<uint8_t>(text[80 + i]);
  const uint64_t needed = 84 + 50 * triangles;
  if (needed != fileSize)
    throw SceneError(fmt::format(
        "{}: the binary STL header declares {} triangles, which need {} bytes, but the file is {} "
        "bytes long",
        prefix, triangles, needed, fileSize));
  // Assimp keeps three positions and three normals per triangle.
  return SceneFootprint{3 * triangles, triangles, triangles * (72 + kBytesPerFace)};
}

}  // namespace

std::optional<SceneFootprint> declaredFootprint(const fs::path& path, uint64_t fileSize,
                                                const std::string& prefix) {
  const std::string ext = lowerExtension(path);
  // Assimp recognises a PLY file by its first bytes whatever its name.
  if (ext == ".ply" || head(path, 4) == "ply\n" || head(path, 5) == "ply\r\n")
    return plyFootprint(path, fileSize, prefix);
  if (ext == ".off") return offFootprint(path, fileSize, prefix);
  if (ext == ".stl") return stlFootprint(path, fileSize, prefix);
  return std::nullopt;
}

}  // namespace sb::detail

// The scheme interface's promises, checked for every registered scheme: parameters are
// validated by name, structures answer within the synthetic intervals, save/load round-trips,
// the file format is pinned by golden files, every truncated or corrupted file is a
// FormatError, never a crash, and so is every crafted one whose checksum was recomputed (run
// under the sanitizers in CI).
#include <catch2/catch.hpp>

#include <sys/resource.h>
#include <sys/stat.h>
#include <xxhash.h>

#include <chrono>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <iterator>
#include <limits>

#include <nlohmann/json.hpp>

#include "schemes/interface/depth_decoder.h"
#include "schemes/interface/lightspace.h"
#include "schemes/interface/serial.h"
#include "tests/support/scratch_dir.h"
#include "tests/support/synthetic_map.h"

using namespace sb;
using sb::testing::ScratchDir;
using sb::testing::SyntheticMap;

namespace {

constexpr uint32_t kGoldenResolution = 8;
constexpr uint64_t kGoldenSeed = 42;

// Answers of a structure at every texel centre and a spread of depths, for comparing two
// structures (a saved one and its reload).
std::vector<float> answersOnGrid(const Decoder& decoder, uint32_t resolution) {
  std::vector<Query> queries;
  for (uint32_t j = 0; j < resolution; ++j)
    for (uint32_t i = 0; i < resolution; ++i)
      for (float z : {0.0f, 0.1f, 0.3f, 0.5f, 0.7f, 0.9f, 1.0f})
        queries.push_back({(i + 0.5f) / resolution, (j + 0.5f) / resolution, z});
  std::vector<float> answers(queries.size());
  for (int k : {1, 3}) decoder.lookup(queries, k, std::span(answers));
  return answers;
}

// A point lookup at every texel: what reaches every part of a loaded structure (a PCF tap is
// a point lookup of a neighbour).
void touchEveryTexel(const Decoder& decoder, uint32_t resolution) {
  std::vector<Query> queries;
  for (uint32_t j = 0; j < resolution; ++j)
    for (uint32_t i = 0; i < resolution; ++i)
      queries.push_back({(i + 0.5f) / resolution, (j + 0.5f) / resolution, 0.5f});
  std::vector<float> answers(queries.size());
  decoder.lookup(queries, 1, std::span(answers));
}

std::vector<uint8_t> readFile(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

void writeFile(const std::filesystem::path& path, std::span<const uint8_t> bytes) {
  std::ofstream(path, std::ios::binary)
      .write(reinterpret_cast<const char*>(bytes.data()), std::streamsize(bytes.size()));
}

// A structure file taken apart along the layout serial.h documents, to craft files whose
// checksum is right: what a hostile user can write, and what the checksum cannot catch.
struct StructureFileParts {
  static constexpr size_t kPrefixBytes = 16;  // magic, version, header length
  std::vector<uint8_t> magicAndVersion;
  std::string header;
  std::vector<uint8_t> payload;

  static StructureFileParts of(std::span<const uint8_t> file) {
    uint32_t headerBytes;
    std::memcpy(&headerBytes, file.data() + 12, 4);
    StructureFileParts parts;
    parts.magicAndVersion.assign(file.begin(), file.begin() + 12);
    parts.header.assign(reinterpret_cast<const char*>(file.data()) + kPrefixBytes, headerBytes);
    const size_t payloadAt = kPrefixBytes + headerBytes + 8;
    parts.payload.assign(file.begin() + payloadAt, file.end() - 8);
    return parts;
  }

  std::vector<uint8_t> join() const {
    std::vector<uint8_t> file = magicAndVersion;
    auto put = [&](const void* data, size_t bytes) {
      file.insert(file.end(), static_cast<const uint8_t*>(data),
                  static_cast<const uint8_t*>(data) + bytes);
    };
    const auto headerBytes = uint32_t(header.size());
    const uint64_t payloadBytes = payload.size();
    put(&headerBytes, 4);
    put(header.data(), header.size());
    put(&payloadBytes, 8);
    put(payload.data(), payload.size());
    const uint64_t checksum = XXH3_64bits(file.data(), file.size());
    put(&checksum, 8);
    return file;
  }
};

std::string formatErrorOf(std::span<const uint8_t> file) {
  try {
    decodeStructureFile(file, nullptr);
  } catch (const FormatError& error) {
    return error.what();
  }
  return "no error";
}

// A file format pinned by a golden file: a scheme with non-default parameters where they
// change the format, at a resolution where they matter.
struct GoldenFormat {
  std::string scheme;
  Params params;
  uint32_t resolution = 8;

  std::string path() const {
    std::string name = scheme;
    for (const auto& [param, value] : params) name += "_" + param + "-" + value;
    return "tests/golden/" + name + ".sb";
  }
};

std::vector<GoldenFormat> goldenFormats() {
  std::vector<GoldenFormat> formats;
  for (const SchemeInfo& scheme : schemes()) formats.push_back({scheme.name, {}});
  // Issue 11: the formats no default reaches. Grid levels are capped at log2 R − 3, treelets
  // of height 5 need 5 levels, and 128-value chunks more than one chunk's values.
  for (const char* voxel : {"cpvs", "cpvs-fast"}) {
    formats.push_back({voxel, {{"leaf-layout", "cube4"}}});
    formats.push_back({voxel, {{"grid-levels", "2"}}, 32});
  }
  formats.push_back({"dag-mh", {{"treelet-height", "5"}}, 32});
  formats.push_back({"dag-mh", {{"chunk-size", "128"}}, 32});
  // Issue 14: float differences, with the byte that says which values the payload holds.
  formats.push_back({"mmh", {{"relative-values", "float-differences"}}});
  return formats;
}

std::vector<uint8_t> goldenFile(const GoldenFormat& format, const Params& params) {
  const SchemeInfo& scheme = findScheme(format.scheme);
  const SyntheticMap map = SyntheticMap::random(format.resolution, DepthMode::Closed, kGoldenSeed);
  const auto decoder = map.build(scheme, params, format.resolution);
  return encodeStructureFile(
      {scheme.name, scheme.resolve(params).text(), map.info(scheme.kind), ""}, *decoder);
}

}  // namespace

TEST_CASE("the registry lists schemes sorted and names them in errors", "[interface]") {
  REQUIRE(!schemes().empty());
  for (size_t s = 1; s < schemes().size(); ++s) CHECK(schemes()[s - 1].name < schemes()[s].name);
  CHECK_THROWS_WITH(findScheme("nope"), Catch::Contains("sm32"));
  CHECK(findScheme("sm32").kind == SchemeKind::Depth);
}

TEST_CASE("texel and voxel addressing follow DESIGN §2 and §4", "[interface]") {
  CHECK(texelOf(0.0f, 8) == 0);
  CHECK(texelOf(0.124999f, 8) == 0);
  CHECK(texelOf(0.125f, 8) == 1);
  CHECK(texelOf(std::nextafter(1.0f, 0.0f), 8) == 7);
  CHECK(!insideMap(texelOf(1.0f, 8), 0, 8));
  CHECK(!insideMap(texelOf(-0.001f, 8), 0, 8));
  CHECK(!insideMap(texelOf(std::nanf(""), 8), 0, 8));
  CHECK(voxelOf(0.0f, 4) == 0);
  CHECK(voxelOf(1.0f, 4) == 3);
  CHECK(voxelOf(-2.0f, 4) == 0);
  CHECK(voxelOf(0.25f, 4) == 1);
  CHECK(voxelCentre(1, 4) == 0.375f);
}

TEST_CASE("every scheme answers inside the intervals of a synthetic map", "[interface]") {
  for (const SchemeInfo& scheme : schemes())
    for (DepthMode mode : {DepthMode::Open, DepthMode::Closed}) {
      INFO(scheme.name << " " << toString(mode));
      const SyntheticMap map = SyntheticMap::random(32, mode, 7);
      const auto decoder = map.build(scheme, {}, 16);
      const MapInfo info = map.info(scheme.kind);
      std::vector<Query> queries;
      std::vector<int> expected;  // 1 lit, 0 shadowed
      for (uint32_t j = 0; j < 32; ++j)
        for (uint32_t i = 0; i < 32; ++i) {
          const float lo = map.lo[j * 32 + i], hi = map.hi[j * 32 + i];
          for (float z : {lo, std::nextafter(lo, -1.0f), std::nextafter(hi, 2.0f), 0.0f}) {
            const float tested =
                scheme.kind == SchemeKind::Voxel
                    ? voxelCentre(voxelOf(z, info.depthResolution), info.depthResolution)
                    : z;
            if (tested <= lo || tested > hi) {
              queries.push_back({(i + 0.25f) / 32, (j + 0.75f) / 32, z});
              expected.push_back(tested <= lo);
            }
          }
        }
      std::vector<float> got(queries.size());
      decoder->lookup(queries, 1, got);
      size_t wrong = 0;
      for (size_t q = 0; q < got.size(); ++q) wrong += got[q] != float(expected[q]);
      CHECK(wrong == 0);
    }
}

// Issue 13: kernels that walk a structure once must answer as its taps do, to the bit, also on a
// map without any spatial coherence and with kernels hanging over every edge.
TEST_CASE("every scheme's PCF equals its point lookups composed tap by tap", "[interface]") {
  constexpr uint32_t r = 32;
  for (const SchemeInfo& scheme : schemes())
    for (DepthMode mode : {DepthMode::Open, DepthMode::Closed}) {
      INFO(scheme.name << " " << toString(mode));
      const SyntheticMap map = SyntheticMap::random(r, mode, 17);
      const auto decoder = map.build(scheme, {}, 16);
      const auto centre = [](int64_t i) { return (float(i) + 0.5f) / float(r); };
      size_t wrong = 0;
      for (float z : {0.2f, 0.45f, 0.7f}) {
        std::vector<Query> points;
        for (uint32_t j = 0; j < r; ++j)
          for (uint32_t i = 0; i < r; ++i) points.push_back({centre(i), centre(j), z});
        std::vector<float> lit(points.size()), got(points.size());
        decoder->lookup(points, 1, lit);
        for (int k : {3, 5, 9, 17}) {
          decoder->lookup(points, k, got);
          for (uint32_t j = 0; j < r; ++j)
            for (uint32_t i = 0; i < r; ++i) {
              int taps = 0;
              for (int64_t tj = int64_t(j) - k / 2; tj <= int64_t(j) + k / 2; ++tj)
                for (int64_t ti = int64_t(i) - k / 2; ti <= int64_t(i) + k / 2; ++ti)
                  taps += !insideMap(ti, tj, r) || lit[size_t(tj) * r + size_t(ti)] == 1.0f;
              wrong += got[j * r + i] != float(taps) / float(k * k);
            }
        }
      }
      CHECK(wrong == 0);
    }
}

TEST_CASE("a batch in Morton order: every query once, off-map ones first", "[interface]") {
  const std::vector<Query> queries{
      {0.9f, 0.9f, 0}, {0.1f, 0.1f, 0}, {-1, 0.5f, 0}, {0.6f, 0.1f, 0}, {0.1f, 0.6f, 0}};
  // Texels of an 8² map: (7, 7), (0, 0), off, (4, 0), (0, 4); Morton codes 63, 0, -, 16, 32.
  CHECK(mortonOrder(queries, 8) == std::vector<uint32_t>{2, 1, 3, 4, 0});
  CHECK(mortonOrder({}, 8).empty());
}

TEST_CASE("lookups reject invalid filter sizes and count outside taps as lit", "[interface]") {
  for (const SchemeInfo& scheme : schemes()) {
    INFO(scheme.name);
    const SyntheticMap map = SyntheticMap::random(16, DepthMode::Open, 3);
    const auto decoder = map.build(scheme, {}, 16);
    std::vector<Query> q{{-0.5f, 0.5f, 1.0f}, {0.5f, 1.5f, 1.0f}};
    std::vector<float> out(2);
    for (int bad : {0, 2, 19, -1})
      CHECK_THROWS_AS(decoder->lookup(q, bad, out), std::invalid_argument);
    decoder->lookup(q, 1, out);
    CHECK(out[0] == 1.0f);
    CHECK(out[1] == 1.0f);
  }
}

TEST_CASE("structures round-trip through their files and reject every corruption",
          "[interface][format]") {
  for (const GoldenFormat& format : goldenFormats()) {
    INFO(format.path());
    const SchemeInfo& scheme = findScheme(format.scheme);
    const SyntheticMap map =
        SyntheticMap::random(format.resolution, DepthMode::Closed, kGoldenSeed);
    const auto decoder = map.build(scheme, format.params, format.resolution);
    const std::string sceneHash = "0123456789abcdef";
    const StructureHeader header{scheme.name, scheme.resolve(format.params).text(),
                                 map.info(scheme.kind), sceneHash};
    const std::vector<uint8_t> file = encodeStructureFile(header, *decoder);

    StructureHeader loadedHeader;
    const auto loaded = decodeStructureFile(file, &loadedHeader);
    CHECK(loadedHeader.scheme == scheme.name);
    CHECK(loadedHeader.params == header.params);
    CHECK(loadedHeader.map.resolution == format.resolution);
    CHECK(loadedHeader.map.depthResolution == header.map.depthResolution);
    CHECK(loadedHeader.sceneHash == sceneHash);
    CHECK(answersOnGrid(*loaded, format.resolution) == answersOnGrid(*decoder, format.resolution));
    CHECK(totalBytes(loaded->size()) == totalBytes(decoder->size()));

    for (size_t length = 0; length < file.size(); ++length)
      CHECK_THROWS_AS(decodeStructureFile(std::span(file).first(length), nullptr), FormatError);
    for (size_t at = 0; at < file.size(); ++at) {
      std::vector<uint8_t> corrupted = file;
      corrupted[at] ^= uint8_t(1u << (at % 8));
      CHECK_THROWS_AS(decodeStructureFile(corrupted, nullptr), FormatError);
    }
  }
}

// The checksum stops accidents before a scheme's loader runs; a crafted payload with its
// checksum recomputed reaches the loader, which must refuse it or give a structure whose lookups
// stay in bounds (the sanitizers watch the lookups).
TEST_CASE("every loader refuses or survives crafted payloads of every length",
          "[interface][format]") {
  for (const GoldenFormat& format : goldenFormats()) {
    INFO(format.path());
    const std::vector<uint8_t> file = goldenFile(format, format.params);
    const StructureFileParts parts = StructureFileParts::of(file);
    REQUIRE(parts.join() == file);
    for (size_t length = 0; length < parts.payload.size(); ++length) {
      StructureFileParts truncated = parts;
      truncated.payload.resize(length);
      INFO("payload truncated to " << length << " bytes");
      CHECK_THROWS_AS(decodeStructureFile(truncated.join(), nullptr), FormatError);
    }
    // Every byte of the small payloads; a spread of about 2048 over the larger variants, whose
    // full sweep would take minutes under the sanitizers.
    const size_t stride = parts.payload.size() / 2048 + 1;
    size_t refused = 0;
    for (size_t at = 0; at < parts.payload.size(); at += stride) {
      StructureFileParts corrupted = parts;
      corrupted.payload[at] ^= uint8_t(1u << (at % 8));
      try {
        touchEveryTexel(*decodeStructureFile(corrupted.join(), nullptr), format.resolution);
      } catch (const FormatError&) {
        ++refused;
      }
    }
    CHECK(refused > 0);
  }
}

TEST_CASE("crafted headers with a valid checksum are refused, naming the problem",
          "[interface][format]") {
  const std::vector<uint8_t> file = goldenFile({"sm-zstd", {}}, {});
  const StructureFileParts parts = StructureFileParts::of(file);
  const nlohmann::json header = nlohmann::json::parse(parts.header);
  auto withHeader = [&](const std::string& text) {
    StructureFileParts crafted = parts;
    crafted.header = text;
    return crafted.join();
  };
  auto edited = [&](auto&& edit) {
    nlohmann::json json = header;
    edit(json);
    return withHeader(json.dump());
  };
  REQUIRE(formatErrorOf(withHeader(header.dump())) == "no error");

  // Issue 11: 2^40 + 8 and 8.7 were read as 8 (narrowing), then loaded.
  for (const nlohmann::json& resolution :
       {nlohmann::json((uint64_t(1) << 40) + 8), nlohmann::json((uint64_t(1) << 32) + 8),
        nlohmann::json(8.7), nlohmann::json(8.0), nlohmann::json(-8), nlohmann::json("8"),
        nlohmann::json(1.8446744073709552e19), nlohmann::json(nullptr)}) {
    INFO("resolution " << resolution.dump());
    CHECK_THAT(
        formatErrorOf(edited([&](nlohmann::json& json) { json["resolution"] = resolution; })),
        Catch::Contains("resolution"));
  }
  // A depth scheme has no depth slices.
  for (const nlohmann::json& slices :
       {nlohmann::json(uint64_t(1) << 32), nlohmann::json(8), nlohmann::json(0.0)})
    CHECK_THAT(
        formatErrorOf(edited([&](nlohmann::json& json) { json["depth_resolution"] = slices; })),
        Catch::Contains("depth_resolution"));
  // Keys the writer never writes, or leaves out.
  CHECK_THAT(formatErrorOf(edited([](nlohmann::json& json) { json["colour"] = "red"; })),
             Catch::Contains("unknown key 'colour'"));
  for (const auto& item : header.items()) {
    INFO(item.key());
    CHECK_THAT(formatErrorOf(edited([&](nlohmann::json& json) { json.erase(item.key()); })),
               Catch::Contains(item.key()));
  }
  CHECK_THAT(formatErrorOf(withHeader("[]")), Catch::Contains("not a JSON object"));
  CHECK_THAT(formatErrorOf(withHeader("{")), Catch::Contains("not JSON"));
  // Parameters: strings only, and only what the registry row accepts.
  CHECK_THAT(formatErrorOf(edited([](nlohmann::json& json) { json["params"]["block"] = 64; })),
             Catch::Contains("'block'") && Catch::Contains("not a string"));
  CHECK_THAT(formatErrorOf(edited([](nlohmann::json& json) { json["params"]["block"] = "48"; })),
             Catch::Contains("'block'"));
  CHECK_THAT(formatErrorOf(edited([](nlohmann::json& json) { json["params"]["speed"] = "1"; })),
             Catch::Contains("'speed'"));
  CHECK_THAT(formatErrorOf(edited([](nlohmann::json& json) { json["params"] = "block=64"; })),
             Catch::Contains("params"));
  CHECK_THAT(formatErrorOf(edited([](nlohmann::json& json) { json["mode"] = "ajar"; })),
             Catch::Contains("ajar"));
  CHECK_THAT(formatErrorOf(edited([](nlohmann::json& json) { json["scheme"] = 7; })),
             Catch::Contains("scheme"));
  for (const char* hash : {"0123456789ABCDEF", "0123456789abcde", "0123456789abcdef0", "x"})
    CHECK_THAT(formatErrorOf(edited([&](nlohmann::json& json) { json["scene_hash"] = hash; })),
               Catch::Contains("scene_hash"));
  // The same values written otherwise than the writer writes them.
  CHECK_THAT(formatErrorOf(withHeader(header.dump(1))), Catch::Contains("as this version writes"));
  CHECK_THAT(formatErrorOf(withHeader("{\"resolution\":4096," + header.dump().substr(1))),
             Catch::Contains("as this version writes"));
}

TEST_CASE("a payload under another scheme's header is refused", "[interface][format]") {
  // Issue 11: mh and mmh share a payload format; an mh payload under an mmh header loaded.
  for (const SchemeInfo& payloadScheme : schemes())
    for (const SchemeInfo& headerScheme : schemes()) {
      if (payloadScheme.name == headerScheme.name) continue;
      INFO(payloadScheme.name << " payload under a " << headerScheme.name << " header");
      StructureFileParts crafted = StructureFileParts::of(goldenFile({headerScheme.name, {}}, {}));
      crafted.payload = StructureFileParts::of(goldenFile({payloadScheme.name, {}}, {})).payload;
      CHECK_THROWS_AS(decodeStructureFile(crafted.join(), nullptr), FormatError);
    }
  StructureFileParts crafted = StructureFileParts::of(goldenFile({"mmh", {}}, {}));
  crafted.payload = StructureFileParts::of(goldenFile({"mh", {}}, {})).payload;
  CHECK_THAT(formatErrorOf(crafted.join()), Catch::Contains("'mh'") && Catch::Contains("'mmh'"));
}

TEST_CASE("sm32 refuses depths its encoder never writes", "[interface][format]") {
  // Issue 11: NaN, infinite and negative depths loaded. The encoder stores lo ∈ [0, 1].
  const StructureFileParts parts = StructureFileParts::of(goldenFile({"sm32", {}}, {}));
  auto withLastDepth = [&](float depth) {
    StructureFileParts crafted = parts;
    std::memcpy(crafted.payload.data() + crafted.payload.size() - sizeof depth, &depth,
                sizeof depth);
    return crafted.join();
  };
  constexpr float kInf = std::numeric_limits<float>::infinity();
  for (float bad : {std::nanf(""), kInf, -kInf, -0.5f, std::nextafter(0.0f, -1.0f),
                    std::nextafter(1.0f, 2.0f), 2.0f}) {
    INFO(bad);
    CHECK_THAT(formatErrorOf(withLastDepth(bad)), Catch::Contains("sm32 depths"));
  }
  for (float good : {0.0f, -0.0f, 0.5f, 1.0f}) {
    INFO(good);
    CHECK(formatErrorOf(withLastDepth(good)) == "no error");
  }
}

TEST_CASE("the writer refuses a scene hash the reader would refuse", "[interface][format]") {
  const SchemeInfo& scheme = findScheme("sm32");
  const SyntheticMap map = SyntheticMap::random(8, DepthMode::Open, 1);
  const auto decoder = map.build(scheme, {}, 8);
  for (const char* hash : {"0123456789ABCDEF", "abc", "0123456789abcdeg"})
    CHECK_THROWS_AS(encodeStructureFile({scheme.name, {}, map.info(scheme.kind), hash}, *decoder),
                    std::invalid_argument);
}

TEST_CASE("a valid checksum does not make an inconsistent header acceptable",
          "[interface][format]") {
  const SchemeInfo& scheme = findScheme("sm32");
  const SyntheticMap map = SyntheticMap::random(16, DepthMode::Open, 1);
  const auto decoder = map.build(scheme, {}, 16);
  for (uint32_t claimed : {8u, 32u, 12u}) {
    // The header claims another resolution than the payload holds, checksum recomputed.
    const StructureHeader header{scheme.name, {}, {claimed, 0, DepthMode::Open}, ""};
    CHECK_THROWS_AS(decodeStructureFile(encodeStructureFile(header, *decoder), nullptr),
                    FormatError);
  }
  const StructureHeader unknown{"no-such-scheme", {}, {16, 0, DepthMode::Open}, ""};
  CHECK_THROWS_WITH(decodeStructureFile(encodeStructureFile(unknown, *decoder), nullptr),
                    Catch::Contains("no-such-scheme"));
}

namespace {

long peakResidentKiB() {
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  return usage.ru_maxrss;
}

std::string loadError(const std::filesystem::path& path) {
  try {
    loadStructure(path, nullptr);
  } catch (const FormatError& error) {
    return error.what();
  }
  return "no error";
}

}  // namespace

TEST_CASE("loading reads a file's header before its payload and only regular files",
          "[interface][format]") {
  const ScratchDir dir;
  const std::vector<uint8_t> file = goldenFile({"mh", {}}, {});
  const std::filesystem::path good = dir.path() / "good.sb";
  writeFile(good, file);
  StructureHeader header;
  CHECK(answersOnGrid(*loadStructure(good, &header), kGoldenResolution) ==
        answersOnGrid(*decodeStructureFile(file, nullptr), kGoldenResolution));
  CHECK(header.scheme == "mh");

  // Issue 11: `query /dev/zero` or any huge file read it whole before looking at the magic.
  constexpr uint64_t kHuge = uint64_t(4) << 30;
  const std::filesystem::path zeros = dir.path() / "zeros.sb";
  std::ofstream(zeros).close();
  std::filesystem::resize_file(zeros, kHuge);  // sparse: no disk, no memory
  // A structure's prefix, header and payload length, then 4 GiB the payload length disagrees with.
  const std::filesystem::path grown = dir.path() / "grown.sb";
  const StructureFileParts parts = StructureFileParts::of(file);
  writeFile(grown,
            std::span(file).first(StructureFileParts::kPrefixBytes + parts.header.size() + 8));
  std::filesystem::resize_file(grown, kHuge);

  const long peakBefore = peakResidentKiB();
  const auto start = std::chrono::steady_clock::now();
  CHECK_THAT(loadError(zeros), Catch::Contains("zeros.sb") && Catch::Contains("bad magic"));
  CHECK_THAT(loadError(grown), Catch::Contains("grown.sb") && Catch::Contains("payload length"));
  CHECK(std::chrono::steady_clock::now() - start < std::chrono::seconds(2));
  CHECK(peakResidentKiB() - peakBefore < 64 * 1024);

  CHECK_THAT(loadError("/dev/zero"), Catch::Contains("not a regular file"));
  CHECK_THAT(loadError(dir.path()), Catch::Contains("not a regular file"));
  const std::filesystem::path fifo = dir.path() / "fifo";
  REQUIRE(mkfifo(fifo.c_str(), 0600) == 0);
  CHECK_THAT(loadError(fifo),
             Catch::Contains("not a regular file"));  // without waiting for a writer
  CHECK_THAT(loadError(dir.path() / "absent.sb"),
             Catch::Contains("absent.sb") && Catch::Contains("cannot open"));
  const std::filesystem::path tiny = dir.path() / "tiny.sb";
  writeFile(tiny, std::span(file).first(20));
  CHECK_THAT(loadError(tiny), Catch::Contains("shorter than any"));
  // What `query` of a cut file says (tests/cli_test.sh), wherever the cut falls.
  for (size_t length : {size_t(40), size_t(200), file.size() - 1}) {
    INFO(length);
    writeFile(tiny, std::span(file).first(length));
    CHECK_THAT(loadError(tiny), Catch::Contains("truncated or corrupted"));
  }
}

// Each format is pinned by tests/golden/<scheme>[_<param>-<value>].sb; regenerate deliberately
// with SHADOWBENCH_UPDATE_GOLDEN=1 when a format version changes.
TEST_CASE("file formats match their golden files", "[interface][format]") {
  for (const GoldenFormat& format : goldenFormats()) {
    const std::string path = format.path();
    INFO("golden file " << path << " (create it with SHADOWBENCH_UPDATE_GOLDEN=1)");
    const std::vector<uint8_t> file = goldenFile(format, format.params);
    if (std::getenv("SHADOWBENCH_UPDATE_GOLDEN")) writeFile(path, file);
    const std::vector<uint8_t> golden = readFile(path);
    REQUIRE(!golden.empty());
    CHECK(golden == file);
    const SyntheticMap map =
        SyntheticMap::random(format.resolution, DepthMode::Closed, kGoldenSeed);
    const auto decoder = map.build(findScheme(format.scheme), format.params, format.resolution);
    CHECK(answersOnGrid(*decodeStructureFile(golden, nullptr), format.resolution) ==
          answersOnGrid(*decoder, format.resolution));
    // A variant pins a format of its own only if its parameters change the payload.
    if (!format.params.empty())
      CHECK(StructureFileParts::of(file).payload !=
            StructureFileParts::of(goldenFile(format, {})).payload);
  }
}

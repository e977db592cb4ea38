// Builds in parts through the harness (issue 12): the merged cell answers as the whole build and
// records its part size, shared depth time and merge; a build resumes from its part files, encodes
// a damaged one again, refuses another build's naming the field, names a missing part; the part
// file format is pinned by a golden file and every truncation or corruption of it is refused.
#include <catch2/catch.hpp>

#include <cstdlib>
#include <fstream>

#include "harness/cell.h"
#include "harness/cell_key.h"
#include "harness/part_file.h"
#include "harness/verify.h"
#include "tests/support/scratch_dir.h"

using namespace sb;
using sb::testing::ScratchDir;

namespace {

const Scene& smallCity() {
  static const Scene scene = openScene("city:size=2,seed=1");
  return scene;
}

CellSpec smallCell(const std::string& scheme, uint32_t partSize) {
  return {"city:size=2,seed=1", 0, DepthMode::Closed, scheme, {}, 256, 32, partSize};
}

CellOptions quickOptions(const std::filesystem::path& partsRoot) {
  CellOptions options;
  options.benchLookups = false;
  options.partsRoot = partsRoot;
  return options;
}

std::filesystem::path folderOf(const CellSpec& cell, const CellOptions& options) {
  return partsFolder(options.partsRoot, cellIdentity(cell, smallCity()));
}

std::vector<uint8_t> readBytes(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), {}};
}

void writeBytes(const std::filesystem::path& path, std::span<const uint8_t> bytes) {
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out.write(reinterpret_cast<const char*>(bytes.data()), std::streamsize(bytes.size()));
}

std::string mergeError(const CellSpec& cell, const CellOptions& options) {
  try {
    mergeCell(cell, smallCity(), options);
  } catch (const std::exception& error) {
    return error.what();
  }
  return "";
}

PartIdentity goldenIdentity() {
  PartIdentity identity;
  identity.structure = {"sm32", {}, {16, 0, DepthMode::Closed}, "0123456789abcdef"};
  identity.light = {{"type", "directional"}, {"direction", {0.0, 0.0, -1.0}}};
  identity.tileSize = 8;
  identity.partSize = 8;
  identity.part = 3;
  return identity;
}

}  // namespace

TEST_CASE("a cell built in parts answers as the whole build and records how it was built",
          "[parts]") {
  ScratchDir dir;
  const CellOptions options = quickOptions(dir.path());
  const Record whole = runCell(smallCell("sm32", 0), smallCity(), options);
  const Record parts = runCell(smallCell("sm32", 64), smallCity(), options);
  CHECK(parts.verification->mismatches == 0);
  CHECK(parts.verification->queries == whole.verification->queries);
  CHECK(parts.sizeBytes == whole.sizeBytes);
  CHECK(parts.partSize == 64);
  CHECK(whole.partSize == 0);
  CHECK(parts.time->phases.count("merge") == 1);
  CHECK(parts.memory->estimatedBytes > 0);
  CHECK(cellKey(parts) != cellKey(whole));
  CHECK(readableCellKey(parts).find("_parts-64") != std::string::npos);
}

TEST_CASE("several schemes share one depth pass, whole and in parts", "[parts]") {
  ScratchDir dir;
  const CellOptions options = quickOptions(dir.path());
  for (uint32_t partSize : {0u, 128u}) {
    INFO("part size " << partSize);
    const std::vector<CellSpec> cells = {smallCell("sm32", partSize),
                                         smallCell(partSize ? "sm32" : "sm-zstd", partSize)};
    std::vector<CellSpec> distinct = {cells[0]};
    if (!partSize) distinct.push_back(cells[1]);
    std::vector<Record> records;
    runCells(distinct, smallCity(), options,
             [&](size_t, const Record& record) { records.push_back(record); });
    REQUIRE(records.size() == distinct.size());
    for (const Record& record : records) CHECK(record.verification->mismatches == 0);
    if (!partSize) {
      CHECK(records[0].time->depthSharedWith == std::vector<std::string>{"sm-zstd"});
      CHECK(records[1].time->depthSharedWith == std::vector<std::string>{"sm32"});
      CHECK(records[0].time->depth == records[1].time->depth);
    }
  }
  // Cells of different maps cannot share a pass.
  const std::vector<CellSpec> mixed = {
      smallCell("sm32", 0), {"city:size=2,seed=1", 0, DepthMode::Open, "sm32", {}, 256, 32, 0}};
  CHECK_THROWS_WITH(runCells(mixed, smallCity(), options, [](size_t, const Record&) {}),
                    Catch::Contains("must share scene, light, mode"));
}

TEST_CASE("schemes that write the same part payload share one part encoder", "[parts]") {
  ScratchDir dir;
  const CellOptions options = quickOptions(dir.path());
  const std::vector<CellSpec> cells = {smallCell("mh", 64), smallCell("mmh", 64),
                                       smallCell("sm32", 64), smallCell("dag-mh", 64)};
  std::vector<Record> records(cells.size());
  runCells(cells, smallCity(), options,
           [&](size_t cell, const Record& record) { records.at(cell) = record; });
  for (const Record& record : records) CHECK(record.verification->mismatches == 0);
  CHECK(records[0].time->encoderSharedWith == std::vector<std::string>{"mmh", "dag-mh"});
  CHECK(records[1].time->encoderSharedWith == std::vector<std::string>{"mh", "dag-mh"});
  CHECK(records[2].time->encoderSharedWith.empty());
  CHECK(records[3].time->depthSharedWith == std::vector<std::string>{"mh", "mmh", "sm32"});
  // One encoder's payload in each scheme's part file, under each scheme's own tag.
  const PartFile mh = decodePartFile(readBytes(partFilePath(folderOf(cells[0], options), 5)));
  const PartFile dagMh = decodePartFile(readBytes(partFilePath(folderOf(cells[3], options), 5)));
  CHECK(std::ranges::equal(mh.payload, dagMh.payload));
  CHECK(mh.costs.phases == dagMh.costs.phases);
  // The pass declares one MH encoder, not three (issue 12: checkCellsFit counted it per scheme).
  const auto encoderBytes = [](const char* name) {
    const SchemeInfo& scheme = findScheme(name);
    return scheme.buildBytes(mapFor(scheme, DepthMode::Closed, 256), scheme.resolve({}),
                             {32, 64, BuildShape::Step::EncodePart});
  };
  CHECK(mh.costs.estimatedBytes == encoderBytes("mh") + encoderBytes("sm32"));
  for (const Record& record : records) {
    REQUIRE(record.memory->parts);
    REQUIRE(record.memory->merge);
    CHECK(record.memory->parts->estimatedBytes == mh.costs.estimatedBytes);
    CHECK(record.memory->merge->estimatedBytes > 0);
    CHECK(record.memory->merge->peakRssBytes > 0);
  }
}

TEST_CASE("a build in parts resumes from its part files and encodes only what is missing",
          "[parts]") {
  ScratchDir dir;
  const CellOptions options = quickOptions(dir.path());
  const CellSpec cell = smallCell("sm32", 64);
  const std::vector<CellSpec> cells = {cell};
  CHECK(encodeCellParts(cells, smallCity(), options, 5).encoded == 1);
  CHECK_THAT(mergeError(cell, options),
             Catch::Contains("15 of 16 part files of sm32 are missing") &&
                 Catch::Contains("part-000000.sbpart"));
  PartsEncoded rest = encodeCellParts(cells, smallCity(), options, std::nullopt);
  CHECK(rest.encoded == 15);
  CHECK(rest.kept == 1);

  const std::filesystem::path folder = folderOf(cell, options);
  const std::filesystem::path damaged = partFilePath(folder, 7);
  std::vector<uint8_t> bytes = readBytes(damaged);
  bytes[bytes.size() / 2] ^= 0x40;
  writeBytes(damaged, bytes);
  std::filesystem::remove(partFilePath(folder, 9));
  rest = encodeCellParts(cells, smallCity(), options, std::nullopt);
  CHECK(rest.encoded == 2);
  CHECK(rest.kept == 14);
  CHECK(mergeCell(cell, smallCity(), options).verification->mismatches == 0);
  CHECK_THROWS_WITH(encodeCellParts(cells, smallCity(), options, 16),
                    Catch::Contains("part 16 does not exist: the map has 16 parts"));
}

TEST_CASE("a merge that fails leaves the other cells of its set merged and recorded",
          "[parts][regression]") {
  // Issue 12: a six-scheme row whose one merge did not fit lost the merges after it.
  ScratchDir dir;
  const CellOptions options = quickOptions(dir.path());
  const std::vector<CellSpec> cells = {smallCell("sm32", 64), smallCell("mh", 64)};
  encodeCellParts(cells, smallCity(), options, std::nullopt);
  std::filesystem::remove(partFilePath(folderOf(cells[0], options), 3));
  std::vector<size_t> merged;
  CHECK_THROWS_WITH(mergeCells(cells, smallCity(), options,
                               [&](size_t cell, const Record& record) {
                                 CHECK(record.verification->mismatches == 0);
                                 merged.push_back(cell);
                               }),
                    Catch::Contains("1 of 2 merges failed") &&
                        Catch::Contains("sm32: 1 of 16 part files of sm32 are missing"));
  CHECK(merged == std::vector<size_t>{1});
}

TEST_CASE("a part file of another build is refused, naming what differs, and kept", "[parts]") {
  ScratchDir dir;
  const CellOptions options = quickOptions(dir.path());
  const CellSpec cell = smallCell("sm32", 64);
  runCell(cell, smallCity(), options);
  const std::filesystem::path folder = folderOf(cell, options);

  struct Foreign {
    CellSpec spec;
    std::string named;
  };
  CellSpec otherResolution = smallCell("sm32", 64);
  otherResolution.resolution = 512;
  CellSpec otherPartSize = smallCell("sm32", 128);
  CellSpec otherMode = smallCell("sm32", 64);
  otherMode.mode = DepthMode::Open;
  CellSpec otherScene = smallCell("sm32", 64);
  otherScene.sceneSpec = "city:size=2,seed=2";
  for (const Foreign& foreign :
       {Foreign{otherResolution, "resolution 512 where this build has 256"},
        Foreign{otherPartSize, "part size 128 where this build has 64"},
        Foreign{otherMode, "mode open where this build has closed"},
        Foreign{otherScene, "scene hash"}}) {
    INFO(foreign.named);
    const Scene& scene =
        foreign.spec.sceneSpec == cell.sceneSpec ? smallCity() : openScene(foreign.spec.sceneSpec);
    ScratchDir otherDir;
    const CellOptions otherOptions = quickOptions(otherDir.path());
    const std::vector<CellSpec> one = {foreign.spec};
    encodeCellParts(one, scene, otherOptions, 0);
    const std::filesystem::path stray =
        partFilePath(partsFolder(otherDir.path(), cellIdentity(foreign.spec, scene)), 0);
    const std::vector<uint8_t> original = readBytes(partFilePath(folder, 0));
    std::filesystem::copy_file(stray, partFilePath(folder, 0),
                               std::filesystem::copy_options::overwrite_existing);
    const std::vector<uint8_t> strayBytes = readBytes(stray);
    CHECK_THAT(mergeError(cell, options), Catch::Contains(foreign.named));
    CHECK_THROWS_WITH(encodeCellParts(std::vector<CellSpec>{cell}, smallCity(), options, 0),
                      Catch::Contains(foreign.named));
    CHECK(readBytes(partFilePath(folder, 0)) == strayBytes);  // nothing overwritten
    writeBytes(partFilePath(folder, 0), original);
  }
  // Another scheme's file, under this scheme's name.
  CellSpec otherScheme = smallCell("sm32", 64);
  PartIdentity wrong = goldenIdentity();
  wrong.structure.scheme = "sm-zstd";
  wrong.structure.params = findScheme("sm-zstd").resolve({}).text();
  const std::vector<uint8_t> file = encodePartFile(wrong, {}, std::vector<uint8_t>(4));
  writeBytes(partFilePath(folder, 0), file);
  CHECK_THAT(mergeError(otherScheme, options), Catch::Contains("belongs to another build"));
}

// tests/golden/part_file.sbpart pins the part file's framing and header, its payload compressed;
// tests/golden/part_file_uncompressed.sbpart the same file as written before compression, which
// still reads. Regenerate deliberately with SHADOWBENCH_UPDATE_GOLDEN=1 when the format changes.
TEST_CASE("the part file format matches its golden files and refuses every damaged copy",
          "[parts][format]") {
  PartCosts costs;
  costs.depthSeconds = 0.5;
  costs.wallSeconds = 1.25;
  costs.phases = {{"encode", 0.75}};
  costs.counters = {{"texels", 64}};
  costs.peakRssBytes = 1 << 20;
  costs.depthSharedWith = {"mh"};
  const std::vector<float> depths(64, 0.5f);
  ByteWriter payload;
  payload.putArray<float>(depths);
  for (const bool compress : {true, false}) {
    const std::vector<uint8_t> file =
        encodePartFile(goldenIdentity(), costs, payload.bytes(), compress);
    const std::string path =
        compress ? "tests/golden/part_file.sbpart" : "tests/golden/part_file_uncompressed.sbpart";
    if (std::getenv("SHADOWBENCH_UPDATE_GOLDEN")) writeBytes(path, file);
    INFO("golden file " << path << " (create it with SHADOWBENCH_UPDATE_GOLDEN=1)");
    CHECK(readBytes(path) == file);

    const PartFile decoded = decodePartFile(file);
    CHECK(decoded.identity.part == 3);
    CHECK(decoded.costs.phases == costs.phases);
    CHECK(decoded.costs.depthSharedWith == costs.depthSharedWith);
    CHECK(std::vector<uint8_t>(decoded.payload.begin(), decoded.payload.end()) == payload.bytes());

    for (size_t length = 0; length < file.size(); ++length) {
      INFO("cut to " << length << " bytes");
      CHECK_THROWS_AS(decodePartFile({file.begin(), file.begin() + std::ptrdiff_t(length)}),
                      FormatError);
    }
    for (size_t at = 0; at < file.size(); at += 7) {
      INFO("byte " << at << " flipped");
      std::vector<uint8_t> corrupted = file;
      corrupted[at] ^= 0x5a;
      CHECK_THROWS_AS(decodePartFile(corrupted), FormatError);
    }
  }
}

// Past the checksum (a file framed anew around them): a compressed payload that is not one whole
// zstd frame of the size its header names, and a compression this build does not know.
TEST_CASE("a part file's compressed payload is refused where it is not one whole zstd frame",
          "[parts][format]") {
  ByteWriter payload;
  payload.putArray<float>(std::vector<float>(64, 0.25f));
  const std::vector<uint8_t> file = encodePartFile(goldenIdentity(), {}, payload.bytes());
  const FramedFile framed = unframeFile(kPartFraming, file);
  const std::string header(framed.header);
  const std::vector<uint8_t> tagged(framed.payload.begin(), framed.payload.end());
  const size_t tagBytes = 1 + goldenIdentity().structure.scheme.size();
  const auto error = [](const std::string& header, std::span<const uint8_t> tagged) {
    try {
      decodePartFile(frameFile(kPartFraming, header, tagged));
    } catch (const FormatError& refused) {
      return std::string(refused.what());
    }
    return std::string();
  };
  REQUIRE(error(header, tagged).empty());
  std::vector<uint8_t> cut(tagged.begin(), tagged.end() - 1), longer = tagged, garbled = tagged;
  longer.push_back(0);
  garbled[tagBytes + 4] ^= 0xff;  // the frame header's first byte after the magic number
  CHECK_THAT(error(header, cut), Catch::Contains("compressed payload"));
  CHECK_THAT(error(header, longer), Catch::Contains("not one whole zstd frame"));
  CHECK_THAT(error(header, garbled), Catch::Contains("compressed payload"));
  const auto replaced = [&](const std::string& from, const std::string& to) {
    std::string text = header;
    REQUIRE(text.find(from) != std::string::npos);
    return text.replace(text.find(from), from.size(), to);
  };
  CHECK_THAT(error(replaced("\"zstd\"", "\"gzip\""), tagged),
             Catch::Contains("\"compression\":\"gzip\""));
  const std::string bytes = std::to_string(payload.bytes().size()),
                    fewer = std::to_string(payload.bytes().size() - 1);
  CHECK_THAT(error(replaced("\"bytes\":" + bytes, "\"bytes\":" + fewer), tagged),
             Catch::Contains("where the header says " + fewer));
}

// A merge declares its memory from what the parts hold: a compressed part's payload as its
// header says, decompressed; a part written before compression, its file's size.
TEST_CASE("a part file's payload bytes are read from its header alone", "[parts][format]") {
  ScratchDir dir;
  ByteWriter payload;
  payload.putArray<float>(std::vector<float>(1000, 0.25f));
  for (const bool compress : {true, false}) {
    const std::vector<uint8_t> file =
        encodePartFile(goldenIdentity(), {}, payload.bytes(), compress);
    const std::filesystem::path path = dir.path() / "part.sbpart";
    writeBytes(path, file);
    CHECK(partPayloadBytes(path) == (compress ? payload.bytes().size() : file.size()));
    if (compress) CHECK(file.size() < payload.bytes().size() / 4);
  }
}

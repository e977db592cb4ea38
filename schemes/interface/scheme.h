// The one encoder/decoder interface every compressed shadow-map scheme implements (DESIGN §5).
//
// A scheme sees only light space: the dual depth map of DESIGN §3 arrives tile by tile as
// DualDepthTiles; the decoder answers batches of point and PCF queries. Schemes never time,
// print or write files: they name their build phases and counters through BuildContext and
// the harness measures.
#pragma once

#include <algorithm>
#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <span>
#include <stdexcept>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "schemes/interface/params.h"

namespace sb {

class ByteReader;
class ByteWriter;
class PartEncoder;  // schemes/interface/parts.h
class PartMerger;
struct MapPart;
class HierarchicalLookup;  // schemes/interface/capabilities.h
class VoxelOccupancy;
class BlockCacheStatistics;

// DESIGN §3: how the interval [lo, hi] of a texel is defined.
enum class DepthMode { Open, Closed, Static };
std::string_view toString(DepthMode mode);
DepthMode depthModeFromString(std::string_view name);  // throws std::invalid_argument

// Depth schemes return a depth per texel; voxel schemes quantise z to Rz slices (DESIGN §4).
enum class SchemeKind { Depth, Voxel };
std::string_view toString(SchemeKind kind);

// What a structure describes: an R×R map (R a power of two) in one mode, with Rz depth slices
// for voxel schemes.
struct MapInfo {
  uint32_t resolution = 0;
  uint32_t depthResolution = 0;  // Rz; voxel schemes only (DESIGN default Rz = R)
  DepthMode mode = DepthMode::Open;
  uint64_t texelCount() const { return uint64_t(resolution) * resolution; }
};

// A rectangle of the dual depth map: texels [x0, x0 + width) × [y0, y0 + height), row-major.
// A texel whose ray hits nothing has lo = 1 and hi = +inf.
struct DualDepthTile {
  uint32_t x0 = 0, y0 = 0, width = 0, height = 0;
  std::vector<float> lo, hi;

  void resize(uint32_t x, uint32_t y, uint32_t w, uint32_t h) {
    x0 = x, y0 = y, width = w, height = h;
    lo.resize(size_t(w) * h);
    hi.resize(size_t(w) * h);
  }
  size_t index(uint32_t i, uint32_t j) const { return size_t(j - y0) * width + (i - x0); }
};

// A light-space query point: x, y in [0, 1) across the map, z in [0, 1] from near to far.
struct Query {
  float x, y, z;
};

// Bytes a lookup may touch, by named component (DESIGN §5: nothing that only the build needs).
using SizeBreakdown = std::vector<std::pair<std::string, uint64_t>>;
uint64_t totalBytes(const SizeBreakdown& sizes);

// Throws std::invalid_argument unless k is an odd filter size in [1, 17] and there is an answer
// slot per query: what every Decoder::lookup checks first.
void checkLookupArguments(std::span<const Query> queries, int k, std::span<float> visibility);

class Decoder {
 public:
  virtual ~Decoder() = default;
  // For each query, the fraction of the k×k texels centred on the query texel that are lit at
  // the query's depth (k odd, 1 ≤ k ≤ 17; k = 1 is the point test, 1 lit or 0 shadowed).
  // Taps outside the map count as lit.
  virtual void lookup(std::span<const Query> queries, int k, std::span<float> visibility) const = 0;
  virtual SizeBreakdown size() const = 0;
  // The scheme's payload; the harness wraps it in the versioned, checksummed file.
  virtual void save(ByteWriter& out) const = 0;

  // Optional lookups (capabilities.h): null where the structure does not offer them.
  virtual const HierarchicalLookup* hierarchicalLookup() const { return nullptr; }
  virtual const VoxelOccupancy* voxelOccupancy() const { return nullptr; }
  virtual const BlockCacheStatistics* blockCacheStatistics() const { return nullptr; }
};

// The harness's side of a build: phase boundaries and counters a scheme reports, timed and
// recorded by the harness.
class BuildContext {
 public:
  virtual ~BuildContext() = default;
  // Everything from now until the next phase() call (or the build's end) belongs to `name`.
  virtual void phase(std::string_view name) = 0;
  virtual void count(std::string_view name, uint64_t value) = 0;
  // Before a step whose memory follows counts known only during the build (the distinct packs a
  // hash-consing finds): `bytes` more than the process holds now. The harness throws where they
  // are not available (`what` names the scheme and the step), before they are taken, and counts
  // them in the build's declared memory.
  virtual void reserve(uint64_t bytes, std::string_view what) = 0;
};

class Encoder {
 public:
  virtual ~Encoder() = default;
  // Tiles arrive in the harness's fixed order (square tiles in Morton order, each once).
  virtual void consume(const DualDepthTile& tile, BuildContext& context) = 0;
  virtual std::unique_ptr<Decoder> finish(BuildContext& context) = 0;
};

// How the harness shapes a build: what a scheme's working memory depends on beside the map (the
// tile size its encoders receive, and the part size of a build in parts).
struct BuildShape {
  // Which step of a build in parts the memory is declared for: a part encoder, the merge, or
  // the build as a whole (the larger of the two).
  enum class Step { Whole, EncodePart, Merge };

  BuildShape(uint32_t tileSize = 512, uint32_t partSize = 0, Step step = Step::Whole)
      : tileSize(tileSize), partSize(partSize), step(step) {}

  uint32_t tileSize = 512;
  uint32_t partSize = 0;  // 0: a whole build; else a power of two in [tileSize, R) (parts.h)
  Step step = Step::Whole;
  // For the merge once the parts exist: their part files' bytes, all together and the largest.
  // A merge's memory follows what the parts hold, which no floor known before them predicts
  // (issue 12: forest:full static at 128K² keeps 4× the nodes of the closed city's floor).
  struct PartFiles {
    uint64_t totalBytes = 0, largestBytes = 0;
  } partFiles;

  bool inParts(const MapInfo& map) const { return partSize != 0 && partSize < map.resolution; }
  // A build in parts' declared bytes for this step, from those of one part encoder and the merge.
  uint64_t partsBytes(uint64_t encodePart, uint64_t merge) const {
    return step == Step::EncodePart ? encodePart
           : step == Step::Merge    ? merge
                                    : std::max(encodePart, merge);
  }
};

struct SchemeInfo {
  std::string name;
  std::string paper;  // the citation, for tables and --help
  SchemeKind kind = SchemeKind::Depth;
  std::vector<ParamSpec> params;
  // Bytes the build needs at least, working memory and the structure it grows together: for
  // refusing, before starting, a resolution that cannot fit. For a build in parts
  // (shape.inParts), those of shape.step: BuildShape::partsBytes(part encoder, merge); the
  // merge's from shape.partFiles when they are known.
  std::function<uint64_t(const MapInfo&, const ParamValues&, const BuildShape&)> buildBytes;
  std::function<std::unique_ptr<Encoder>(const MapInfo&, const ParamValues&, const BuildShape&)>
      makeEncoder;
  // Reads a payload written by Decoder::save, validating everything: a structure that loads
  // never reads out of bounds at lookup time. Throws FormatError.
  std::function<std::unique_ptr<Decoder>(ByteReader&, const MapInfo&, const ParamValues&)> load;
  // Builds in parts (parts.h); both null for a scheme that builds only whole.
  std::function<std::unique_ptr<PartEncoder>(const MapInfo&, const MapPart&, const ParamValues&,
                                             const BuildShape&)>
      makePartEncoder;
  // The merge's shape carries its part files' sizes (BuildShape::partFiles).
  std::function<std::unique_ptr<PartMerger>(const MapInfo&, const ParamValues&, const BuildShape&)>
      makePartMerger;
  // Schemes whose part encoders write the same payload, whatever their parameters, name it alike
  // here ("" for a payload of the scheme's own): a depth pass feeding several of them runs one
  // part encoder and gives each its payload (issue 12: MH, MMH and DAG-MH differ only in the
  // merge).
  std::string partPayload;
  bool buildsInParts() const { return makePartEncoder && makePartMerger; }

  // Defaults filled in, every value checked against its spec; throws ParamError.
  ParamValues resolve(const Params& given) const;
};

// The registry: schemes add themselves with SHADOWBENCH_REGISTER_SCHEME in their own folder.
const std::vector<SchemeInfo>& schemes();
const SchemeInfo& findScheme(std::string_view name);  // throws std::invalid_argument naming them
bool registerScheme(SchemeInfo info);

#define SHADOWBENCH_REGISTER_SCHEME(info_function)                   \
  [[maybe_unused]] static const bool sb_registered_##info_function = \
      ::sb::registerScheme(info_function())

}  // namespace sb

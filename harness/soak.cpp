#include "harness/soak.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <stdexcept>

#include <fmt/format.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include "harness/reference.h"
#include "schemes/interface/lightspace.h"
#include "schemes/interface/morton.h"
#include "schemes/interface/splitmix.h"

namespace sb {

namespace {

constexpr int kPcfFilters[] = {3, 5, 9, 17};

// The reference intervals of one tile; a tap outside it is a bug in the query placement.
struct TileIntervals {
  const DualDepthTile& tile;
  DepthInterval operator()(int64_t i, int64_t j) const {
    if (i < tile.x0 || j < tile.y0 || i >= int64_t(tile.x0) + tile.width ||
        j >= int64_t(tile.y0) + tile.height)
      throw std::logic_error("soak query tap outside its tile");
    const size_t t = tile.index(uint32_t(i), uint32_t(j));
    return {tile.lo[t], tile.hi[t]};
  }
};

// A coordinate inside texel i: its lower edge, the last float before its upper edge, or a point
// `jitter` of the way across (DESIGN §2: texel i is [i/R, (i+1)/R), and R is a power of two, so
// i/R is exact).
enum class Placement { LowerEdge, UpperEdge, Inside };
float coordinateIn(int64_t i, uint32_t resolution, Placement placement, float jitter) {
  switch (placement) {
    case Placement::LowerEdge:
      return float(double(i) / resolution);
    case Placement::UpperEdge:
      return std::nextafter(float(double(i + 1) / resolution), 0.0f);
    case Placement::Inside:
      break;
  }
  const float x = float((double(i) + jitter) / resolution);
  return texelOf(x, resolution) == i ? x : float((double(i) + 0.5) / resolution);
}

Placement placementOf(uint64_t random) {
  return Placement(random % 3);
}

// The depths at which a texel's answer changes or must hold: lo and hi with the floats either
// side, a depth inside the undefined band, 0 and 1, and for voxel schemes the edges of the
// slices holding lo and hi (DESIGN §4's voxel rule decides there). Clamped to [0, 1].
float boundaryDepth(DepthInterval in, SchemeKind kind, const MapInfo& map, uint64_t random) {
  const float hi = std::isfinite(in.hi) ? in.hi : 1.0f;  // nothing hit: only "beyond 1" is above
  const int choices = kind == SchemeKind::Voxel ? 14 : 10;
  float z = 0;
  switch (random % uint64_t(choices)) {
    case 0:
      z = in.lo;
      break;
    case 1:
      z = std::nextafter(in.lo, -1.0f);
      break;
    case 2:
      z = std::nextafter(in.lo, 2.0f);
      break;
    case 3:
      z = hi;
      break;
    case 4:
      z = std::nextafter(hi, -1.0f);
      break;
    case 5:
      z = std::nextafter(hi, 2.0f);
      break;
    case 6:
      z = in.lo + (hi - in.lo) * 0.5f;
      break;
    case 7:
      z = 0.0f;
      break;
    case 8:
      z = 1.0f;
      break;
    case 9:
      z = std::nextafter(1.0f, 0.0f);
      break;
    case 10:
      z = float(voxelOf(in.lo, map.depthResolution)) / float(map.depthResolution);
      break;
    case 11:
      z = std::nextafter(float(voxelOf(in.lo, map.depthResolution)) / float(map.depthResolution),
                         -1.0f);
      break;
    case 12:
      z = float(voxelOf(hi, map.depthResolution) + 1) / float(map.depthResolution);
      break;
    default:
      z = std::nextafter(float(voxelOf(hi, map.depthResolution) + 1) / float(map.depthResolution),
                         -1.0f);
      break;
  }
  return std::clamp(z, 0.0f, 1.0f);
}

struct BatchResult {
  uint64_t queries = 0, mismatches = 0;
  std::vector<Mismatch> examples;  // in query order, at most kSoakMaxExamples
};

class TileChecker {
 public:
  TileChecker(const Decoder& decoder, SchemeKind kind, const MapInfo& map,
              const DualDepthTile& tile)
      : decoder_(decoder), kind_(kind), map_(map), tile_(tile), intervals_{tile} {}

  // Batch `batch` of the tile, drawn from `random`: point queries, uniform and at boundaries,
  // then PCF queries of one filter size.
  BatchResult check(uint64_t batch, uint64_t random) const {
    std::vector<Query> points(kSoakBatchQueries - kSoakPcfPerBatch), pcf(kSoakPcfPerBatch);
    for (Query& q : points) q = pointQuery(random);
    const int k = kPcfFilters[batch % std::size(kPcfFilters)];
    for (Query& q : pcf) q = pcfQuery(k, random);
    BatchResult result;
    judge(points, 1, result);
    judge(pcf, k, result);
    return result;
  }

 private:
  int64_t randomIn(int64_t first, int64_t last, uint64_t& random) const {
    return first + int64_t(nextRandom(random) % uint64_t(last - first + 1));
  }

  // Half uniform (texel, position and depth), half at boundaries: a quarter of those on the
  // tile's edge rows and columns (the map's border in border tiles), at a texel edge or corner,
  // at a depth where the answer changes.
  Query pointQuery(uint64_t& random) const {
    const uint64_t r = nextRandom(random);
    const int64_t x0 = tile_.x0, y0 = tile_.y0, x1 = x0 + tile_.width - 1,
                  y1 = y0 + tile_.height - 1;
    int64_t i = randomIn(x0, x1, random), j = randomIn(y0, y1, random);
    const float jx = unitFloat(nextRandom(random)), jy = unitFloat(nextRandom(random));
    if (r % 2 == 0)
      return {coordinateIn(i, map_.resolution, Placement::Inside, jx),
              coordinateIn(j, map_.resolution, Placement::Inside, jy),
              unitFloat(nextRandom(random))};
    if ((r >> 1) % 4 == 0) {
      const uint64_t side = (r >> 3) % 4;
      if (side < 2)
        j = side == 0 ? y0 : y1;
      else
        i = side == 2 ? x0 : x1;
    }
    return {coordinateIn(i, map_.resolution, placementOf(r >> 5), jx),
            coordinateIn(j, map_.resolution, placementOf(r >> 7), jy),
            boundaryDepth(intervals_(i, j), kind_, map_, r >> 9)};
  }

  // The centres whose k×k taps inside the map all lie in the tile: k/2 texels in from the
  // tile's edges, except along the map's border.
  std::pair<int64_t, int64_t> centreRange(uint32_t origin, uint32_t size, int k) const {
    const int64_t radius = k / 2;
    const int64_t first = origin == 0 ? 0 : int64_t(origin) + radius;
    const int64_t last = int64_t(origin) + size == map_.resolution
                             ? int64_t(map_.resolution) - 1
                             : int64_t(origin) + size - 1 - radius;
    return {first, last};
  }

  // At the centre's lo, just beyond its hi, at a random tap's lo, or at a uniform depth.
  Query pcfQuery(int k, uint64_t& random) const {
    const auto [xFirst, xLast] = centreRange(tile_.x0, tile_.width, k);
    const auto [yFirst, yLast] = centreRange(tile_.y0, tile_.height, k);
    const int64_t i = randomIn(xFirst, xLast, random), j = randomIn(yFirst, yLast, random);
    const uint64_t r = nextRandom(random);
    const float x = coordinateIn(i, map_.resolution, placementOf(r), unitFloat(nextRandom(random)));
    const float y =
        coordinateIn(j, map_.resolution, placementOf(r >> 2), unitFloat(nextRandom(random)));
    const DepthInterval centre = intervals_(i, j);
    float z = unitFloat(nextRandom(random));
    switch ((r >> 4) % 4) {
      case 0:
        z = centre.lo;
        break;
      case 1:
        z = std::isfinite(centre.hi) ? std::nextafter(centre.hi, 2.0f) : 1.0f;
        break;
      case 2: {
        const int64_t ti =
            std::clamp<int64_t>(i + randomIn(-k / 2, k / 2, random), 0, map_.resolution - 1);
        const int64_t tj =
            std::clamp<int64_t>(j + randomIn(-k / 2, k / 2, random), 0, map_.resolution - 1);
        z = intervals_(ti, tj).lo;
        break;
      }
      default:
        break;
    }
    return {x, y, std::clamp(z, 0.0f, 1.0f)};
  }

  void judge(const std::vector<Query>& queries, int k, BatchResult& result) const {
    std::vector<float> got(queries.size());
    decoder_.lookup(queries, k, got);
    for (size_t q = 0; q < queries.size(); ++q) {
      const int64_t i = texelOf(queries[q].x, map_.resolution),
                    j = texelOf(queries[q].y, map_.resolution);
      const VisibilityRange expected =
          acceptedRange(kind_, map_, i, j, k, queries[q].z, intervals_);
      if (expected.contains(got[q])) continue;
      ++result.mismatches;
      if (result.examples.size() < kSoakMaxExamples)
        result.examples.push_back({queries[q], k, got[q], expected});
    }
    result.queries += queries.size();
  }

  const Decoder& decoder_;
  SchemeKind kind_;
  const MapInfo& map_;
  const DualDepthTile& tile_;
  TileIntervals intervals_;
};

template <class T>
T field(const nlohmann::json& json, const char* name) {
  if (!json.is_object() || !json.contains(name))
    throw std::invalid_argument(fmt::format("soak state: field '{}' is missing", name));
  try {
    return json[name].get<T>();
  } catch (const nlohmann::json::exception&) {
    throw std::invalid_argument(fmt::format("soak state: field '{}' has the wrong type", name));
  }
}

}  // namespace

nlohmann::json SoakState::toJson() const {
  return {{"format", kSoakStateFormat}, {"identity", identity}, {"tiles_total", tilesTotal},
          {"tiles_done", tilesDone},    {"seconds", seconds},   {"report", report.toJson()}};
}

SoakState SoakState::fromJson(const nlohmann::json& json) {
  if (field<std::string>(json, "format") != kSoakStateFormat)
    throw std::invalid_argument(fmt::format("soak state: format is not '{}'", kSoakStateFormat));
  SoakState state;
  state.identity = field<nlohmann::json>(json, "identity");
  state.tilesTotal = field<uint64_t>(json, "tiles_total");
  state.tilesDone = field<uint64_t>(json, "tiles_done");
  state.seconds = field<double>(json, "seconds");
  if (state.tilesDone > state.tilesTotal)
    throw std::invalid_argument("soak state: more tiles done than there are");
  const nlohmann::json report = field<nlohmann::json>(json, "report");
  state.report.method = field<std::string>(report, "method");
  state.report.queries = field<uint64_t>(report, "queries");
  state.report.mismatches = field<uint64_t>(report, "mismatches");
  for (const nlohmann::json& m : field<nlohmann::json>(report, "examples")) {
    const auto expected = field<std::vector<float>>(m, "expected");
    if (expected.size() != 2)
      throw std::invalid_argument("soak state: an example's 'expected' is not [min, max]");
    state.report.examples.push_back(
        {{field<float>(m, "x"), field<float>(m, "y"), field<float>(m, "z")},
         field<int>(m, "k"),
         field<float>(m, "got"),
         {expected[0], expected[1]}});
  }
  return state;
}

SoakState newSoakState(const nlohmann::json& structure, const MapInfo& map,
                       const SoakOptions& options) {
  const uint32_t t = options.tileSize;
  if (t < 32 || t > map.resolution || (t & (t - 1)) != 0)
    throw std::invalid_argument(
        fmt::format("soak tile size {} must be a power of two from 32 to the resolution {}", t,
                    map.resolution));
  SoakState state;
  state.identity = {{"structure", structure},
                    {"resolution", map.resolution},
                    {"depth_resolution", map.depthResolution},
                    {"mode", toString(map.mode)},
                    {"seed", options.seed},
                    {"queries_per_tile", options.queriesPerTile},
                    {"tile_size", t}};
  state.tilesTotal = uint64_t(map.resolution / t) * (map.resolution / t);
  state.report.method = "soak";
  return state;
}

SoakState resumeSoakState(const nlohmann::json& saved, const SoakState& fresh) {
  SoakState state = SoakState::fromJson(saved);
  // Flattened, so that the error names the innermost field ("/structure/scene_hash").
  const nlohmann::json ours = fresh.identity.flatten(), theirs = state.identity.flatten();
  for (const auto& [key, value] : ours.items())
    if (!theirs.contains(key) || theirs[key] != value)
      throw std::runtime_error(
          fmt::format("the soak state is of another run: its {} is {}, this run's is {}", key,
                      theirs.contains(key) ? theirs[key].dump() : "missing", value.dump()));
  for (const auto& [key, value] : theirs.items())
    if (!ours.contains(key))
      throw std::runtime_error(
          fmt::format("the soak state is of another run: it has {}, this run has not", key));
  if (state.tilesTotal != fresh.tilesTotal)
    throw std::runtime_error(
        fmt::format("the soak state is of another run: it has {} tiles, this run {}",
                    state.tilesTotal, fresh.tilesTotal));
  return state;
}

void soak(const Decoder& decoder, SchemeKind kind, const MapInfo& map, const DepthSource& source,
          const SoakOptions& options, SoakState& state,
          const std::function<void(const SoakState&)>& tileDone) {
  if (source.resolution() != map.resolution || source.mode() != map.mode)
    throw std::invalid_argument("soak: the depth source is not of the structure's map");
  const uint32_t tilesPerSide = map.resolution / options.tileSize;
  if (state.tilesTotal != uint64_t(tilesPerSide) * tilesPerSide)
    throw std::invalid_argument("soak: the state is not of these options");
  const uint64_t batches =
      std::max<uint64_t>(1, (options.queriesPerTile + kSoakBatchQueries - 1) / kSoakBatchQueries);
  const auto start = std::chrono::steady_clock::now();
  const double secondsBefore = state.seconds;
  // A few tiles traced in parallel, then checked in Morton order: done tiles are never traced
  // again, and a stop (an exception from tileDone) leaves nothing in flight. A tile's intervals
  // are those of a build's stream whatever the order of tracing (DESIGN §3, depth_source.h).
  const size_t inFlight = size_t(tbb::this_task_arena::max_concurrency());
  std::vector<DualDepthTile> tiles(inFlight);
  while (!state.finished()) {
    const uint64_t first = state.tilesDone;
    const uint64_t count = std::min<uint64_t>(inFlight, state.tilesTotal - first);
    tbb::parallel_for(uint64_t(0), count, [&](uint64_t n) {
      source.trace(mortonX(first + n) * options.tileSize, mortonY(first + n) * options.tileSize,
                   options.tileSize, options.tileSize, tiles[n]);
    });
    for (uint64_t n = 0; n < count; ++n) {
      const uint64_t t = first + n;
      const TileChecker checker(decoder, kind, map, tiles[n]);
      std::vector<BatchResult> results(batches);
      tbb::parallel_for(uint64_t(0), batches, [&](uint64_t b) {
        results[b] = checker.check(b, mixBits(options.seed ^ mixBits(t ^ mixBits(b))));
      });
      for (BatchResult& r : results) {
        state.report.queries += r.queries;
        state.report.mismatches += r.mismatches;
        for (const Mismatch& m : r.examples)
          if (state.report.examples.size() < kSoakMaxExamples) state.report.examples.push_back(m);
      }
      state.tilesDone = t + 1;
      state.seconds =
          secondsBefore +
          std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
      if (tileDone) tileDone(state);
    }
  }
}

}  // namespace sb

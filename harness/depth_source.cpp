#include "harness/depth_source.h"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <exception>
#include <limits>
#include <mutex>
#include <stdexcept>

#include <embree3/rtcore.h>
#include <fmt/format.h>
#include <tbb/parallel_pipeline.h>
#include <tbb/task_arena.h>

#include "harness/crossings.h"
#include "harness/embree_scene.h"
#include "harness/light_space_rasterizer.h"
#include "harness/resolution.h"
#include "schemes/interface/lightspace.h"
#include "schemes/interface/morton.h"

namespace sb {

namespace {

constexpr float kInfinity = std::numeric_limits<float>::infinity();

// The intersect context handed to Embree: the filter finds each lane's list via the ray id.
struct GatherContext {
  RTCIntersectContext embree;
  const Light* light;
  const int8_t* closedByGeometry;
  CrossingList* lists;
};

// Records every hit and rejects it, so one traversal visits every surface along the ray.
void gatherCrossings(const RTCFilterFunctionNArguments* args) {
  auto* context = reinterpret_cast<const GatherContext*>(args->context);
  for (unsigned lane = 0; lane < args->N; ++lane) {
    if (args->valid[lane] != -1) continue;
    const unsigned geometry = RTCHitN_geomID(args->hit, args->N, lane);
    // Embree's geometric normal is cross(v1 − v0, v2 − v0): outward for a closed mesh.
    const float facing =
        RTCHitN_Ng_x(args->hit, args->N, lane) * RTCRayN_dir_x(args->ray, args->N, lane) +
        RTCHitN_Ng_y(args->hit, args->N, lane) * RTCRayN_dir_y(args->ray, args->N, lane) +
        RTCHitN_Ng_z(args->hit, args->N, lane) * RTCRayN_dir_z(args->ray, args->N, lane);
    const int8_t sign = context->closedByGeometry[geometry] ? (facing < 0 ? 1 : -1) : 0;
    context->lists[RTCRayN_id(args->ray, args->N, lane)].insertOnce(
        {context->light->depthOfHit(RTCRayN_tfar(args->ray, args->N, lane)), sign, geometry});
    args->valid[lane] = 0;
  }
}

}  // namespace

struct DepthSource::Embree {
  Embree(const Scene& scene, const Light& light)
      : rays(
            scene, [&](const glm::vec3& v) { return glm::vec3(light.toView(glm::dvec3(v))); },
            RTC_SCENE_FLAG_CONTEXT_FILTER_FUNCTION, RTC_BUILD_QUALITY_HIGH) {
    for (const uint32_t mesh : rays.meshOfGeometry())
      closedByGeometry.push_back(scene.meshes[mesh].closed);
  }
  EmbreeScene rays;
  std::vector<int8_t> closedByGeometry;
};

std::string_view toString(DepthMethod method) {
  return method == DepthMethod::Rasterize ? "rasterize" : "raycast";
}

DepthSource::DepthSource(const Scene& scene, const Light& light, DepthMode mode,
                         uint32_t resolution, DepthMethod method)
    : light_(light), mode_(mode), resolution_(resolution) {
  if (!validResolution(resolution))
    throw std::invalid_argument(
        fmt::format("resolution {} must be a power of two in [8, 2^20]", resolution));
  embree_ = std::make_unique<Embree>(scene, light);
  if (method == DepthMethod::Rasterize && light.kind() == LightKind::Directional)
    rasterizer_ = std::make_unique<LightSpaceRasterizer>(scene, light, resolution);
}

DepthSource::~DepthSource() = default;

DepthSource::Packet DepthSource::tracePacket(uint32_t i0, uint32_t j0) const {
  Packet packet;
  if (rasterizer_) {
    float lo[kPacketSize], hi[kPacketSize];
    const uint64_t fallbacks =
        rasterizer_->rasterize(i0, j0, kPacketWidth, kPacketHeight, mode_, lo, hi, kPacketWidth);
    if (fallbacks) closedFallbacks_.fetch_add(fallbacks, std::memory_order_relaxed);
    for (uint32_t lane = 0; lane < kPacketSize; ++lane) packet[lane] = {lo[lane], hi[lane]};
    return packet;
  }
  alignas(64) int valid[kPacketSize];
  alignas(64) RTCRayHit16 rays;
  for (uint32_t lane = 0; lane < kPacketSize; ++lane) {
    const PrimaryRay ray =
        light_.texelRay(i0 + lane % kPacketWidth, j0 + lane / kPacketWidth, resolution_);
    valid[lane] = -1;
    rays.ray.org_x[lane] = ray.origin.x, rays.ray.org_y[lane] = ray.origin.y,
    rays.ray.org_z[lane] = ray.origin.z;
    rays.ray.dir_x[lane] = ray.direction.x, rays.ray.dir_y[lane] = ray.direction.y,
    rays.ray.dir_z[lane] = ray.direction.z;
    rays.ray.tnear[lane] = ray.tnear;
    rays.ray.tfar[lane] = ray.tfar;
    rays.ray.time[lane] = 0;
    rays.ray.mask[lane] = ~0u;
    rays.ray.id[lane] = lane;
    rays.ray.flags[lane] = 0;
    rays.hit.geomID[lane] = RTC_INVALID_GEOMETRY_ID;
    rays.hit.instID[0][lane] = RTC_INVALID_GEOMETRY_ID;
  }

  GatherContext context;
  rtcInitIntersectContext(&context.embree);
  context.embree.flags = RTC_INTERSECT_CONTEXT_FLAG_COHERENT;
  if (mode_ == DepthMode::Open) {
    // The first hit is all an open map needs: plain closest-hit traversal.
    rtcIntersect16(valid, embree_->rays.scene(), &context.embree, &rays);
    for (uint32_t lane = 0; lane < kPacketSize; ++lane) {
      const bool hit = rays.hit.geomID[lane] != RTC_INVALID_GEOMETRY_ID;
      const float lo = hit ? light_.depthOfHit(rays.ray.tfar[lane]) : 1.0f;
      packet[lane] = {lo, hit ? lo : kInfinity};
    }
    return packet;
  }

  CrossingList lists[kPacketSize];
  for (CrossingList& list : lists) list.clear(mode_);
  context.embree.filter = gatherCrossings;
  context.light = &light_;
  context.closedByGeometry = embree_->closedByGeometry.data();
  context.lists = lists;
  rtcIntersect16(valid, embree_->rays.scene(), &context.embree, &rays);
  uint64_t fallbacks = 0;
  for (uint32_t lane = 0; lane < kPacketSize; ++lane) {
    const ResolvedInterval resolved = resolveCrossings(lists[lane], mode_);
    packet[lane] = {resolved.lo, resolved.hi};
    fallbacks += resolved.closedFallback;
  }
  if (fallbacks) closedFallbacks_.fetch_add(fallbacks, std::memory_order_relaxed);
  return packet;
}

DepthSource::Hit DepthSource::intersect(const glm::vec3& origin, const glm::vec3& direction) const {
  RTCRayHit ray{};
  ray.ray.org_x = origin.x, ray.ray.org_y = origin.y, ray.ray.org_z = origin.z;
  ray.ray.dir_x = direction.x, ray.ray.dir_y = direction.y, ray.ray.dir_z = direction.z;
  ray.ray.tnear = 0;
  ray.ray.tfar = kInfinity;
  ray.ray.mask = ~0u;
  ray.hit.geomID = RTC_INVALID_GEOMETRY_ID;
  ray.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
  RTCIntersectContext context;
  rtcInitIntersectContext(&context);
  rtcIntersect1(embree_->rays.scene(), &context, &ray);
  if (ray.hit.geomID == RTC_INVALID_GEOMETRY_ID) return {-1.0f, glm::vec3(0.0f)};
  return {ray.ray.tfar, glm::vec3(ray.hit.Ng_x, ray.hit.Ng_y, ray.hit.Ng_z)};
}

DepthInterval DepthSource::texel(uint32_t i, uint32_t j) const {
  const Packet packet = tracePacket(i - i % kPacketWidth, j - j % kPacketHeight);
  return packet[(j % kPacketHeight) * kPacketWidth + i % kPacketWidth];
}

void DepthSource::trace(uint32_t x0, uint32_t y0, uint32_t w, uint32_t h,
                        DualDepthTile& tile) const {
  if (x0 % kPacketWidth || w % kPacketWidth || y0 % kPacketHeight || h % kPacketHeight ||
      uint64_t(x0) + w > resolution_ || uint64_t(y0) + h > resolution_)
    throw std::invalid_argument(
        fmt::format("tile {}x{} at ({}, {}) is not packet-aligned inside the map", w, h, x0, y0));
  tile.resize(x0, y0, w, h);
  if (rasterizer_) {
    const uint64_t fallbacks =
        rasterizer_->rasterize(x0, y0, w, h, mode_, tile.lo.data(), tile.hi.data(), w);
    if (fallbacks) closedFallbacks_.fetch_add(fallbacks, std::memory_order_relaxed);
    return;
  }
  for (uint32_t j0 = y0; j0 < y0 + h; j0 += kPacketHeight)
    for (uint32_t i0 = x0; i0 < x0 + w; i0 += kPacketWidth) {
      const Packet packet = tracePacket(i0, j0);
      for (uint32_t lane = 0; lane < kPacketSize; ++lane) {
        const size_t at = tile.index(i0 + lane % kPacketWidth, j0 + lane / kPacketWidth);
        tile.lo[at] = packet[lane].lo;
        tile.hi[at] = packet[lane].hi;
      }
    }
}

uint32_t defaultTileSize(uint32_t resolution) {
  return std::min<uint32_t>(resolution, 512);
}

namespace {

// Streams the tiles [first, end) of the map's Morton order of tiles.
StreamStats streamTiles(const DepthSource& source, uint32_t tileSize, uint64_t first, uint64_t end,
                        const std::function<void(const DualDepthTile&)>& consume,
                        const std::function<void(uint64_t)>& progress) {
  uint64_t next = first, texelsDone = 0;
  std::atomic<int64_t> traceNanoseconds{0};
  const auto start = std::chrono::steady_clock::now();
  const size_t tokens = size_t(2 * tbb::this_task_arena::max_concurrency());
  // oneTBB does not destroy the tiles in flight when an exception cancels a pipeline (a leak
  // LeakSanitizer reports), so a failure is kept here instead: the input stops, the tiles still
  // in flight drain untouched, and the first exception is rethrown after the pipeline.
  std::exception_ptr failure;
  std::mutex failureMutex;
  std::atomic<bool> failed{false};
  const auto fail = [&] {
    const std::lock_guard lock(failureMutex);
    if (!failure) failure = std::current_exception();
    failed = true;
  };
  tbb::parallel_pipeline(
      tokens, tbb::make_filter<void, uint64_t>(tbb::filter_mode::serial_in_order,
                                               [&](tbb::flow_control& control) -> uint64_t {
                                                 if (next == end || failed) control.stop();
                                                 return next++;
                                               }) &
                  tbb::make_filter<uint64_t, std::shared_ptr<DualDepthTile>>(
                      tbb::filter_mode::parallel,
                      [&](uint64_t morton) -> std::shared_ptr<DualDepthTile> {
                        if (failed) return nullptr;
                        const auto traceStart = std::chrono::steady_clock::now();
                        auto tile = std::make_shared<DualDepthTile>();
                        try {
                          source.trace(mortonX(morton) * tileSize, mortonY(morton) * tileSize,
                                       tileSize, tileSize, *tile);
                        } catch (...) {
                          fail();
                          return nullptr;
                        }
                        traceNanoseconds += std::chrono::duration_cast<std::chrono::nanoseconds>(
                                                std::chrono::steady_clock::now() - traceStart)
                                                .count();
                        return tile;
                      }) &
                  tbb::make_filter<std::shared_ptr<DualDepthTile>, void>(
                      tbb::filter_mode::serial_in_order, [&](std::shared_ptr<DualDepthTile> tile) {
                        if (!tile || failed) return;
                        try {
                          consume(*tile);
                          texelsDone += uint64_t(tile->width) * tile->height;
                          if (progress) progress(texelsDone);
                        } catch (...) {
                          fail();
                        }
                      }));
  if (failure) std::rethrow_exception(failure);
  const std::chrono::duration<double> wall = std::chrono::steady_clock::now() - start;
  return {double(traceNanoseconds.load()) * 1e-9, wall.count()};
}

}  // namespace

StreamStats streamDualDepth(const DepthSource& source, uint32_t tileSize,
                            const std::function<void(const DualDepthTile&)>& consume,
                            const std::function<void(uint64_t)>& progress) {
  if (tileSize == 0) throw std::invalid_argument("tile size 0: pass defaultTileSize(R)");
  checkTileSize(tileSize, source.resolution());
  const uint64_t tilesPerSide = source.resolution() / tileSize;
  return streamTiles(source, tileSize, 0, tilesPerSide * tilesPerSide, consume, progress);
}

StreamStats streamDualDepth(const DepthSource& source, uint32_t tileSize, const MapPart& part,
                            const std::function<void(const DualDepthTile&)>& consume,
                            const std::function<void(uint64_t)>& progress) {
  if (tileSize == 0) throw std::invalid_argument("tile size 0: pass defaultTileSize(R)");
  checkTileSize(tileSize, source.resolution());
  if (tileSize > part.size || part.size > source.resolution())
    throw std::invalid_argument(fmt::format("tile size {} does not fit parts of {}² in a {}² map",
                                            tileSize, part.size, source.resolution()));
  const uint64_t tilesPerPart = uint64_t(part.size / tileSize) * (part.size / tileSize);
  return streamTiles(source, tileSize, part.index * tilesPerPart, (part.index + 1) * tilesPerPart,
                     consume, progress);
}

}  // namespace sb

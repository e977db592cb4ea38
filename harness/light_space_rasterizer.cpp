#include "harness/light_space_rasterizer.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <limits>
#include <stdexcept>

#include <fmt/format.h>
#include <tbb/parallel_for.h>

#include "harness/crossings.h"
#include "schemes/interface/lightspace.h"

namespace sb {

namespace {

// Light space [0, 1) in units of 2^-28: fine enough for 2^20 texels per side with 2^7
// sub-texel steps, and coarse enough that edge functions of differences below 2^29 stay
// exact in 64-bit integers.
constexpr int kFixedBits = 28;
constexpr double kFixedScale = double(1 << kFixedBits);

// The edge function of a→b at p: twice the signed area of (a, b, p), positive when p lies to
// the left of a→b.
inline int64_t edge(int64_t ax, int64_t ay, int64_t bx, int64_t by, int64_t px, int64_t py) {
  return (bx - ax) * (py - ay) - (by - ay) * (px - ax);
}

// The top-left rule for a counter-clockwise triangle: a point exactly on an edge belongs to
// it only when the edge runs downwards, or leftwards along a horizontal line. Of two triangles
// sharing an edge, which they run in opposite directions, exactly one owns it.
inline bool ownsEdge(int64_t dx, int64_t dy) {
  return dy < 0 || (dy == 0 && dx < 0);
}

// Integer division rounding down and up, for a positive divisor.
inline int64_t floorDiv(int64_t a, int64_t b) {
  return a >= 0 ? a / b : -((-a + b - 1) / b);
}
inline int64_t ceilDiv(int64_t a, int64_t b) {
  return -floorDiv(-a, b);
}

// Sutherland–Hodgman: `polygon` clipped to [lo, hi]² in (x, y), z interpolated (linear in an
// orthographic light space). The crossing of an edge is computed from its lexicographically
// smaller end, so two triangles sharing an edge get bit-identical new vertices and stay
// watertight for the closed-mode counter.
void clipToSquare(std::vector<glm::dvec3>& polygon, double lo, double hi,
                  std::vector<glm::dvec3>& scratch) {
  auto lexLess = [](const glm::dvec3& a, const glm::dvec3& b) {
    return a.x < b.x || (a.x == b.x && (a.y < b.y || (a.y == b.y && a.z < b.z)));
  };
  for (int axis = 0; axis < 2; ++axis)
    for (const double bound : {lo, hi}) {
      const double side = bound == lo ? 1.0 : -1.0;  // inside where side·(v − bound) ≥ 0
      scratch.clear();
      for (size_t k = 0; k < polygon.size(); ++k) {
        const glm::dvec3& a = polygon[k];
        const glm::dvec3& b = polygon[(k + 1) % polygon.size()];
        const bool aIn = side * (a[axis] - bound) >= 0, bIn = side * (b[axis] - bound) >= 0;
        if (aIn) scratch.push_back(a);
        if (aIn != bIn) {
          const glm::dvec3& from = lexLess(a, b) ? a : b;
          const glm::dvec3& to = lexLess(a, b) ? b : a;
          const double t = (bound - from[axis]) / (to[axis] - from[axis]);
          glm::dvec3 crossing = from + t * (to - from);
          crossing[axis] = bound;
          scratch.push_back(crossing);
        }
      }
      polygon.swap(scratch);
      if (polygon.size() < 3) return polygon.clear();
    }
}

}  // namespace

LightSpaceRasterizer::LightSpaceRasterizer(const Scene& scene, const Light& light,
                                           uint32_t resolution)
    : resolution_(resolution) {
  if (light.kind() != LightKind::Directional)
    throw std::invalid_argument("the light-space rasteriser handles directional lights only");
  if (!validResolution(resolution))
    throw std::invalid_argument(
        fmt::format("resolution {} must be a power of two in [8, 2^20]", resolution));
  halfTexel_ = int64_t(1) << (kFixedBits - 1 - std::countr_zero(resolution));
  binsPerSide_ = std::clamp<uint32_t>(resolution / 32, 1, 256);
  texelsPerBin_ = resolution / binsPerSide_;

  // The texel centres (2i + 1)·h that lie within [lo, hi].
  auto centresWithin = [&](int64_t lo, int64_t hi, int32_t& first, int32_t& last) {
    const int64_t h = halfTexel_;
    first = int32_t(std::max<int64_t>(0, lo <= h ? 0 : (lo - h + 2 * h - 1) / (2 * h)));
    last = int32_t(std::min<int64_t>(resolution - 1, hi < h ? -1 : (hi - h) / (2 * h)));
  };

  auto addTriangle = [&](const glm::dvec3(&p)[3], bool closed, uint32_t mesh) {
    FixedTriangle t{};
    for (int k = 0; k < 3; ++k) {
      t.x[k] = int32_t(std::llround(p[k].x * kFixedScale));
      t.y[k] = int32_t(std::llround(p[k].y * kFixedScale));
      t.z[k] = float(p[k].z);
    }
    const int64_t area = edge(t.x[0], t.y[0], t.x[1], t.y[1], t.x[2], t.y[2]);
    if (area == 0) return;  // edge-on to the light: its neighbours cover its line
    // Rays run along +z: a face whose normal cross(b − a, c − a) points against them (area <
    // 0) is a front face, entered by the ray.
    t.sign = closed ? (area < 0 ? 1 : -1) : 0;
    t.mesh = mesh;
    if (area < 0) std::swap(t.x[1], t.x[2]), std::swap(t.y[1], t.y[2]), std::swap(t.z[1], t.z[2]);
    centresWithin(*std::min_element(t.x, t.x + 3), *std::max_element(t.x, t.x + 3), t.texelMin[0],
                  t.texelMax[0]);
    centresWithin(*std::min_element(t.y, t.y + 3), *std::max_element(t.y, t.y + 3), t.texelMin[1],
                  t.texelMax[1]);
    if (t.texelMin[0] > t.texelMax[0] || t.texelMin[1] > t.texelMax[1]) return;  // between centres
    triangles_.push_back(t);
  };

  // A light window (Light::window) leaves geometry outside [0, 1)², beyond what fixed point can
  // hold: such triangles are clipped to the map plus two texels, far from every texel centre.
  const double margin = 2.0 / resolution;
  std::vector<glm::dvec3> polygon, clipped;
  for (uint32_t m = 0; m < scene.meshes.size(); ++m) {
    const Mesh& mesh = scene.meshes[m];
    std::vector<glm::dvec3> lightSpace(mesh.vertices.size());
    for (size_t v = 0; v < mesh.vertices.size(); ++v)
      lightSpace[v] = light.toView(glm::dvec3(mesh.vertices[v]));
    for (const glm::uvec3& index : mesh.triangles) {
      const glm::dvec3 p[3] = {lightSpace[index[0]], lightSpace[index[1]], lightSpace[index[2]]};
      const glm::dvec2 lo =
          glm::min(glm::dvec2(p[0]), glm::min(glm::dvec2(p[1]), glm::dvec2(p[2])));
      const glm::dvec2 hi =
          glm::max(glm::dvec2(p[0]), glm::max(glm::dvec2(p[1]), glm::dvec2(p[2])));
      if (lo.x >= -margin && lo.y >= -margin && hi.x <= 1 + margin && hi.y <= 1 + margin) {
        addTriangle(p, mesh.closed, m);
        continue;
      }
      if (hi.x < -margin || hi.y < -margin || lo.x > 1 + margin || lo.y > 1 + margin) continue;
      polygon.assign(p, p + 3);
      clipToSquare(polygon, -margin, 1 + margin, clipped);
      for (size_t k = 1; k + 1 < polygon.size(); ++k)
        addTriangle({polygon[0], polygon[k], polygon[k + 1]}, mesh.closed, m);
    }
  }

  // Bin the triangles by the texel centres their bounding boxes hold: count, then fill.
  binStart_.assign(size_t(binsPerSide_) * binsPerSide_ + 1, 0);
  auto forEachBin = [&](const FixedTriangle& t, auto&& f) {
    for (uint32_t by = t.texelMin[1] / texelsPerBin_; by <= t.texelMax[1] / texelsPerBin_; ++by)
      for (uint32_t bx = t.texelMin[0] / texelsPerBin_; bx <= t.texelMax[0] / texelsPerBin_; ++bx)
        if (!edgesAt(t, int64_t(bx) * texelsPerBin_, int64_t(by) * texelsPerBin_)
                 .miss(texelsPerBin_, texelsPerBin_))
          f(size_t(by) * binsPerSide_ + bx);
  };
  for (const FixedTriangle& t : triangles_)
    forEachBin(t, [&](size_t bin) { ++binStart_[bin + 1]; });
  for (size_t b = 1; b < binStart_.size(); ++b) binStart_[b] += binStart_[b - 1];
  binTriangles_.resize(binStart_.back());
  std::vector<uint32_t> fill(binStart_.begin(), binStart_.end() - 1);
  for (uint32_t index = 0; index < triangles_.size(); ++index)
    forEachBin(triangles_[index], [&](size_t bin) { binTriangles_[fill[bin]++] = index; });
  // Nearest first: crossings then mostly arrive in depth order, so a texel's list appends
  // instead of shifting, and a full list turns the rest away with one comparison. The order is
  // a pure function of the scene, as determinism needs.
  auto nearestFirst = [&](uint32_t a, uint32_t b) {
    const float za = *std::min_element(triangles_[a].z, triangles_[a].z + 3);
    const float zb = *std::min_element(triangles_[b].z, triangles_[b].z + 3);
    return za < zb || (za == zb && a < b);
  };
  tbb::parallel_for(size_t(0), binStart_.size() - 1, [&](size_t bin) {
    std::sort(binTriangles_.begin() + binStart_[bin], binTriangles_.begin() + binStart_[bin + 1],
              nearestFirst);
  });
}

LightSpaceRasterizer::Edges LightSpaceRasterizer::edgesAt(const FixedTriangle& t, int64_t i,
                                                          int64_t j) const {
  const int64_t step = 2 * halfTexel_;
  const int64_t px = (2 * i + 1) * halfTexel_, py = (2 * j + 1) * halfTexel_;
  // Edge k runs from vertex k+1 to vertex k+2, opposite vertex k: its function is vertex k's
  // barycentric weight times twice the area.
  Edges e;
  for (int k = 0; k < 3; ++k) {
    const int a = (k + 1) % 3, b = (k + 2) % 3;
    const int64_t dx = int64_t(t.x[b]) - t.x[a], dy = int64_t(t.y[b]) - t.y[a];
    e.start[k] = edge(t.x[a], t.y[a], t.x[b], t.y[b], px, py);
    e.perColumn[k] = -dy * step;
    e.perRow[k] = dx * step;
    e.need[k] = ownsEdge(dx, dy) ? 0 : 1;
  }
  return e;
}

bool LightSpaceRasterizer::Edges::miss(int64_t columns, int64_t rows) const {
  // Edge functions are linear: a rectangle lies outside an edge when its best corner does.
  for (int k = 0; k < 3; ++k)
    if (start[k] + std::max<int64_t>(0, perColumn[k] * (columns - 1)) +
            std::max<int64_t>(0, perRow[k] * (rows - 1)) <
        need[k])
      return true;
  return false;
}

template <class Visit>
void LightSpaceRasterizer::coverTexels(const FixedTriangle& t, int64_t i0, int64_t i1, int64_t j0,
                                       int64_t j1, Visit&& visit) const {
  i0 = std::max<int64_t>(i0, t.texelMin[0]), i1 = std::min<int64_t>(i1, t.texelMax[0]);
  j0 = std::max<int64_t>(j0, t.texelMin[1]), j1 = std::min<int64_t>(j1, t.texelMax[1]);
  if (i0 > i1 || j0 > j1) return;
  Edges e = edgesAt(t, i0, j0);
  if (e.miss(i1 - i0 + 1, j1 - j0 + 1)) return;  // a sliver's bounding box, not the sliver
  const double inverseArea = 1.0 / double(e.start[0] + e.start[1] + e.start[2]);
  const float zMin = std::min({t.z[0], t.z[1], t.z[2]}), zMax = std::max({t.z[0], t.z[1], t.z[2]});
  // Rows of a wide triangle solve their span by division; a narrow one tests each texel, which
  // is cheaper than three divisions. Both decide exactly the same coverage.
  const bool solveSpans = i1 - i0 >= 16;
  for (int64_t j = j0; j <= j1; ++j) {
    int64_t first = 0, last = i1 - i0;
    for (int k = 0; k < 3 && solveSpans; ++k) {
      if (e.perColumn[k] > 0)
        first = std::max(first, ceilDiv(e.need[k] - e.start[k], e.perColumn[k]));
      else if (e.perColumn[k] < 0)
        last = std::min(last, floorDiv(e.start[k] - e.need[k], -e.perColumn[k]));
      else if (e.start[k] < e.need[k])
        last = -1;
    }
    for (int64_t n = first; n <= last; ++n) {
      const int64_t w[3] = {e.start[0] + n * e.perColumn[0], e.start[1] + n * e.perColumn[1],
                            e.start[2] + n * e.perColumn[2]};
      if (!solveSpans && (w[0] < e.need[0] || w[1] < e.need[1] || w[2] < e.need[2])) continue;
      const double z =
          (double(w[0]) * t.z[0] + double(w[1]) * t.z[1] + double(w[2]) * t.z[2]) * inverseArea;
      visit(i0 + n, j, std::clamp(float(z), zMin, zMax));
    }
    for (int k = 0; k < 3; ++k) e.start[k] += e.perRow[k];
  }
}

uint64_t LightSpaceRasterizer::rasterize(uint32_t x0, uint32_t y0, uint32_t w, uint32_t h,
                                         DepthMode mode, float* lo, float* hi,
                                         size_t stride) const {
  constexpr float kInfinity = std::numeric_limits<float>::infinity();
  constexpr uint32_t kBlock = 32;  // texels per side resolved together: their lists stay in cache
  uint64_t fallbacks = 0;
  std::vector<float> nearest;
  std::vector<CrossingList> lists;
  for (uint32_t by = y0; by < y0 + h; by += kBlock)
    for (uint32_t bx = x0; bx < x0 + w; bx += kBlock) {
      const uint32_t bw = std::min(kBlock, x0 + w - bx), bh = std::min(kBlock, y0 + h - by);
      if (mode == DepthMode::Open) {
        nearest.assign(size_t(bw) * bh, kInfinity);
      } else {
        lists.resize(size_t(bw) * bh);
        for (CrossingList& list : lists) list.clear(mode);
      }
      // Each texel centre lies in exactly one bin, so it meets each triangle once, in bin order.
      for (uint32_t binY = by / texelsPerBin_; binY <= (by + bh - 1) / texelsPerBin_; ++binY)
        for (uint32_t binX = bx / texelsPerBin_; binX <= (bx + bw - 1) / texelsPerBin_; ++binX) {
          const int64_t i0 = std::max(bx, binX * texelsPerBin_),
                        i1 = std::min(bx + bw, (binX + 1) * texelsPerBin_) - 1;
          const int64_t j0 = std::max(by, binY * texelsPerBin_),
                        j1 = std::min(by + bh, (binY + 1) * texelsPerBin_) - 1;
          const size_t bin = size_t(binY) * binsPerSide_ + binX;
          for (uint32_t n = binStart_[bin]; n < binStart_[bin + 1]; ++n) {
            const FixedTriangle& t = triangles_[binTriangles_[n]];
            if (mode == DepthMode::Open)
              coverTexels(t, i0, i1, j0, j1, [&](int64_t i, int64_t j, float z) {
                float& near = nearest[size_t(j - by) * bw + (i - bx)];
                near = std::min(near, z);
              });
            else
              coverTexels(t, i0, i1, j0, j1, [&](int64_t i, int64_t j, float z) {
                lists[size_t(j - by) * bw + (i - bx)].insert({z, t.sign, t.mesh});
              });
          }
        }
      for (uint32_t j = 0; j < bh; ++j)
        for (uint32_t i = 0; i < bw; ++i) {
          const size_t out = size_t(by - y0 + j) * stride + (bx - x0 + i);
          if (mode == DepthMode::Open) {
            const float z = nearest[size_t(j) * bw + i];
            lo[out] = z == kInfinity ? 1.0f : z;
            hi[out] = z;
            continue;
          }
          const ResolvedInterval r = resolveCrossings(lists[size_t(j) * bw + i], mode);
          lo[out] = r.lo, hi[out] = r.hi;
          fallbacks += r.closedFallback;
        }
    }
  return fallbacks;
}

}  // namespace sb

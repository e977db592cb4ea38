// The reference oracle (DESIGN §4): the answer every scheme is checked against, computed by
// re-tracing texels through the depth source, independently of any scheme's data.
#pragma once

#include <cstdint>
#include <vector>

#include "harness/depth_source.h"
#include "schemes/interface/lightspace.h"
#include "schemes/interface/scheme.h"

namespace sb {

enum class PointAnswer { Lit, Shadowed, Undefined };

// The point test of one texel's interval at depth z: lit if z ≤ lo, shadowed if z > hi.
inline PointAnswer pointTest(DepthInterval interval, float z) {
  if (z <= interval.lo) return PointAnswer::Lit;
  if (z > interval.hi) return PointAnswer::Shadowed;
  return PointAnswer::Undefined;
}

// The depth a scheme of `kind` actually tests: z itself, or its voxel's centre.
inline float testedDepth(SchemeKind kind, const MapInfo& map, float z) {
  return kind == SchemeKind::Voxel
             ? voxelCentre(voxelOf(z, map.depthResolution), map.depthResolution)
             : z;
}

// The range a correct k×k PCF answer must lie in: [lit_defined/k², (lit_defined+undefined)/k²].
struct VisibilityRange {
  float min, max;
  bool contains(float v) const { return v >= min && v <= max; }
};

// A window of reference intervals, traced packet by packet through the depth source.
class ReferenceWindow {
 public:
  // Texels [x0, x0 + w) × [y0, y0 + h) clipped to the map and widened to whole packets.
  ReferenceWindow(const DepthSource& source, int64_t x0, int64_t y0, int64_t w, int64_t h);

  bool contains(int64_t i, int64_t j) const { return i >= x0_ && j >= y0_ && i < x1_ && j < y1_; }
  DepthInterval at(int64_t i, int64_t j) const {
    return intervals_[size_t(j - y0_) * (x1_ - x0_) + (i - x0_)];
  }
  int64_t x0() const { return x0_; }
  int64_t y0() const { return y0_; }
  int64_t x1() const { return x1_; }
  int64_t y1() const { return y1_; }

 private:
  int64_t x0_, y0_, x1_, y1_;
  std::vector<DepthInterval> intervals_;
};

}  // namespace sb

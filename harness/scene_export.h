// Outputs for outside checkers: a scene in light space as OBJ, and a dual depth map as EXR.
#pragma once

#include <filesystem>
#include <ostream>

#include "harness/depth_source.h"
#include "harness/light.h"
#include "scenes/scene.h"

namespace sb {

// Every mesh's triangles with vertices in light space (x, y across the map, z the depth in
// [0, 1]), one `o closed_<name>` or `o open_<name>` object per mesh. For directional lights and
// linear spot lights the depth of a texel is exactly the first hit on these triangles.
void exportLightSpaceObj(const Scene& scene, const Light& light, std::ostream& out);

// The largest map writeDualDepthExr writes: both channels are in memory at once.
inline constexpr uint32_t kMaxExrResolution = 16384;

// The whole dual depth map as a two-channel float EXR ("lo", "hi"); R ≤ kMaxExrResolution.
void writeDualDepthExr(const DepthSource& source, const std::filesystem::path& path);

}  // namespace sb

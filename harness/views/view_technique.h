// Shadow techniques as a viewer sees them (DESIGN §5b): each frame a technique prepares what it
// holds for the camera (view-dependent ones rebuild their maps; a precomputed structure does
// nothing) and then shades the frame's visible surface. The harness times both steps, scores the
// answers against the ray-traced ground truth and writes the records; techniques never time,
// print or write files.
#pragma once

#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "harness/light.h"
#include "harness/views/camera_path.h"
#include "harness/views/ground_truth.h"
#include "scenes/scene.h"
#include "schemes/interface/params.h"
#include "schemes/interface/scheme.h"

namespace sb {

class ViewTechnique {
 public:
  virtual ~ViewTechnique() = default;
  // Builds what the frame's lookups need, from the camera and the frame's visible surface (the
  // G-buffer a deferred renderer has before its shadow pass; truth.lit is not read).
  virtual void prepare(const Camera& camera, const GroundTruth& surface) = 0;
  // Per pixel, the visibility of its visible point in [0, 1] (0 where not covered).
  virtual void shade(const Camera& camera, const GroundTruth& surface,
                     std::vector<float>& visibility) = 0;
  // Bytes the lookups of this frame may touch.
  virtual uint64_t memoryBytes() const = 0;
  // What this frame's preparation chose (cascade splits, tile resolutions), for the record.
  virtual nlohmann::json frameLayout() const { return nlohmann::json::object(); }
};

// The nearest and farthest view depth the frame shows: the near and far planes that CSM's splits
// and IASM's frustum extent are fitted to.
struct ViewDepthRange {
  bool any = false;
  double nearest = 0, farthest = 0;
};
ViewDepthRange viewDepthRange(const GroundTruth& surface);

// A view-dependent technique's registry row: its parameters declared and defaulted here, so
// the CLI, tests and records enumerate them as they do a scheme's.
struct ViewTechniqueRow {
  std::string name;
  std::string paper;
  std::vector<ParamSpec> params;
  std::function<std::unique_ptr<ViewTechnique>(const Scene&, const Light&, const ParamValues&)>
      make;
};

const std::vector<ViewTechniqueRow>& viewTechniques();
// Throws std::invalid_argument naming the known techniques.
const ViewTechniqueRow& findViewTechnique(std::string_view name);

// The depth schemes' and voxel schemes' light-space test for every pixel: a saved structure
// looked up at each visible point moved along its normal by `offsetTexels` texels of the
// structure (Kämpe §4's normal offset), with a k×k filter; points outside the map are lit.
std::unique_ptr<ViewTechnique> makeStructureTechnique(const Light& light, const Decoder& decoder,
                                                      uint32_t resolution, uint64_t bytes, int k,
                                                      double offsetTexels);

}  // namespace sb

// One camera path, every technique, every frame: the ground truth traced once per frame, each
// technique prepared and shaded (timed here, in the harness), scored, and pictured; one view
// record per technique (DESIGN §5b, §6).
#pragma once

#include <cstdint>
#include <filesystem>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "harness/light.h"
#include "harness/views/camera_path.h"
#include "harness/views/view_technique.h"
#include "scenes/scene.h"

namespace sb {

// The format tag and version of a view record.
inline constexpr const char* kViewRecordFormat = "shadowbench-view-record";
inline constexpr int kViewRecordVersion = 1;

struct ViewEntry {
  std::string name;          // "csm", "iasm", or the structure's scheme
  std::string kind;          // "view-dependent" or "precomputed"
  std::string label;         // unique in the run: names its record and image folder
  nlohmann::json params;     // the technique's or scheme's parameters, as text
  nlohmann::json structure;  // precomputed: scheme, params, mode, resolution, file; else null
  std::unique_ptr<ViewTechnique> technique;
};

struct ViewRunOptions {
  std::filesystem::path out;          // records: out/<label>.json; images: out/images/…
  std::vector<uint32_t> imageFrames;  // frames whose pictures are written
  bool exr = true;                    // also the EXR of each written picture's visibility
  uint32_t boundaryRadius = 2;        // pixels; see shadowBoundary
  double normalOffset = 0;            // of the occlusion rays (ground truth), world units
  int filter = 1;                     // k of the precomputed structures' k×k lookups
};

struct ViewScene {
  const Scene& scene;
  std::string spec;
  const Light& light;
};

// Runs the path; returns the records in `entries`' order (also written, atomically, as
// out/<label>.json). `frameDone` (optional) is called after each frame.
std::vector<nlohmann::json> runViews(const ViewScene& scene, const CameraPath& path,
                                     const std::filesystem::path& pathFile,
                                     std::vector<ViewEntry>& entries, const ViewRunOptions& options,
                                     const std::function<void(uint32_t)>& frameDone = {});

// "iasm (importance=same-frame)": the technique and the parameters that differ from its
// registry defaults (`specs`), then `suffix` ("16K² closed" for a structure); safe as a file
// name once slugged (viewSlug). The record keeps every parameter.
std::string viewLabel(const std::string& name, const Params& params,
                      const std::vector<ParamSpec>& specs, const std::string& suffix = "");
std::string viewSlug(const std::string& label);

}  // namespace sb

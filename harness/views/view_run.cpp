#include "harness/views/view_run.h"

#include <algorithm>
#include <chrono>

#include <fmt/format.h>

#include "harness/machine.h"
#include "harness/source_commit.h"
#include "harness/views/frame_images.h"
#include "harness/views/frame_score.h"
#include "harness/views/ground_truth.h"
#include "schemes/interface/atomic_file.h"

namespace fs = std::filesystem;

namespace sb {

namespace {

using Clock = std::chrono::steady_clock;

double millisecondsSince(Clock::time_point start) {
  return std::chrono::duration<double, std::milli>(Clock::now() - start).count();
}

double median(std::vector<double> values) {
  if (values.empty()) return 0;
  std::sort(values.begin(), values.end());
  const size_t n = values.size();
  return n % 2 ? values[n / 2] : (values[n / 2 - 1] + values[n / 2]) / 2;
}

std::string utcNow() {
  const auto now = std::chrono::system_clock::to_time_t(std::chrono::system_clock::now());
  std::tm tm{};
  gmtime_r(&now, &tm);
  return fmt::format("{:04}-{:02}-{:02}T{:02}:{:02}:{:02}Z", tm.tm_year + 1900, tm.tm_mon + 1,
                     tm.tm_mday, tm.tm_hour, tm.tm_min, tm.tm_sec);
}

// Writes the PNG (and EXR) of a picture; returns the PNG's path relative to the records folder.
std::string writePicture(const fs::path& out, const fs::path& relative, const RgbImage& image,
                         const GroundTruth& truth, std::span<const float> visibility, bool exr) {
  fs::create_directories((out / relative).parent_path());
  writePng(out / relative, image);
  if (exr) {
    fs::path exrPath = out / relative;
    writeVisibilityExr(exrPath.replace_extension(".exr"), truth.width, truth.height, truth.covered,
                       visibility);
  }
  return relative.generic_string();
}

}  // namespace

std::string viewLabel(const std::string& name, const Params& params,
                      const std::vector<ParamSpec>& specs, const std::string& suffix) {
  std::string changed;
  for (const ParamSpec& spec : specs)
    if (const auto it = params.find(spec.name);
        it != params.end() && it->second != spec.defaultValue)
      changed += fmt::format("{}{}={}", changed.empty() ? "" : ", ", spec.name, it->second);
  std::string label = suffix.empty() ? name : name + " " + suffix;
  return changed.empty() ? label : fmt::format("{} ({})", label, changed);
}

std::string viewSlug(const std::string& label) {
  std::string slug;
  for (const char c : label) {
    const bool keep = std::isalnum(static_cast<unsigned char>(c)) || c == '.';
    if (keep)
      slug += c;
    else if (!slug.empty() && slug.back() != '-')
      slug += '-';
  }
  while (!slug.empty() && slug.back() == '-') slug.pop_back();
  return slug;
}

std::vector<nlohmann::json> runViews(const ViewScene& view, const CameraPath& path,
                                     const fs::path& pathFile, std::vector<ViewEntry>& entries,
                                     const ViewRunOptions& options,
                                     const std::function<void(uint32_t)>& frameDone) {
  const SceneRays rays(view.scene);
  const LightSpec& lightSpec = view.light.spec();
  std::vector<nlohmann::json> frames(entries.size(), nlohmann::json::array());
  std::vector<FrameScore> totals(entries.size());
  std::vector<std::vector<double>> buildMs(entries.size()), shadeMs(entries.size());
  std::vector<uint64_t> peakMemory(entries.size(), 0);
  std::vector<float> visibility;

  for (uint32_t f = 0; f < path.frames.size(); ++f) {
    const Camera& camera = path.frames[f];
    const GroundTruth truth =
        traceGroundTruth(rays, lightSpec, camera, path.width, path.height, options.normalOffset);
    const std::vector<uint8_t> boundary =
        shadowBoundary(truth.width, truth.height, truth.covered, truth.lit, options.boundaryRadius);
    const bool pictured = std::find(options.imageFrames.begin(), options.imageFrames.end(), f) !=
                          options.imageFrames.end();
    std::string truthPicture;
    if (pictured) {
      std::vector<float> truthVisibility(truth.lit.begin(), truth.lit.end());
      truthPicture =
          writePicture(options.out, fmt::format("images/truth/truth-{:03}.png", f),
                       shadowMaskImage(truth.width, truth.height, truth.covered, truthVisibility),
                       truth, truthVisibility, options.exr);
    }
    for (size_t e = 0; e < entries.size(); ++e) {
      ViewTechnique& technique = *entries[e].technique;
      const Clock::time_point built = Clock::now();
      technique.prepare(camera, truth);
      const double prepareMs = millisecondsSince(built);
      const Clock::time_point shaded = Clock::now();
      technique.shade(camera, truth, visibility);
      const double shadeMsFrame = millisecondsSince(shaded);
      const FrameScore score = scoreFrame(truth.covered, truth.lit, boundary, visibility);
      totals[e] += score;
      buildMs[e].push_back(prepareMs);
      shadeMs[e].push_back(shadeMsFrame);
      peakMemory[e] = std::max(peakMemory[e], technique.memoryBytes());
      nlohmann::json frame = score.toJson();
      frame["frame"] = f;
      frame["memory_bytes"] = technique.memoryBytes();
      frame["build_ms"] = prepareMs;
      frame["shade_ms"] = shadeMsFrame;
      frame["layout"] = technique.frameLayout();
      if (pictured) {
        const std::string folder = "images/" + viewSlug(entries[e].label);
        frame["images"] = {
            {"truth", truthPicture},
            {"mask",
             writePicture(options.out, fmt::format("{}/mask-{:03}.png", folder, f),
                          shadowMaskImage(truth.width, truth.height, truth.covered, visibility),
                          truth, visibility, options.exr)},
            {"error", writePicture(options.out, fmt::format("{}/error-{:03}.png", folder, f),
                                   errorImage(truth.width, truth.height, truth.covered, truth.lit,
                                              visibility),
                                   truth, visibility, false)}};
      }
      frames[e].push_back(std::move(frame));
    }
    if (frameDone) frameDone(f + 1);
  }

  const nlohmann::json machine = machineInfo();
  const std::string commit = sourceCommit(SHADOWBENCH_SOURCE_DIR);
  std::vector<nlohmann::json> records;
  for (size_t e = 0; e < entries.size(); ++e) {
    nlohmann::json totalsJson = totals[e].toJson();
    totalsJson["memory_bytes"] = peakMemory[e];
    totalsJson["build_ms_median"] = median(buildMs[e]);
    totalsJson["shade_ms_median"] = median(shadeMs[e]);
    nlohmann::json record = {{"format", kViewRecordFormat},
                             {"version", kViewRecordVersion},
                             {"scene",
                              {{"spec", view.spec},
                               {"name", view.scene.name},
                               {"hash", view.scene.hash()},
                               {"triangles", view.scene.triangleCount()}}},
                             {"light", view.light.describe()},
                             {"path",
                              {{"name", path.name},
                               {"file", pathFile.generic_string()},
                               {"frames", path.frames.size()},
                               {"width", path.width},
                               {"height", path.height}}},
                             {"technique",
                              {{"name", entries[e].name},
                               {"kind", entries[e].kind},
                               {"label", entries[e].label},
                               {"params", entries[e].params},
                               {"structure", entries[e].structure}}},
                             {"filter", entries[e].kind == "precomputed" ? options.filter : 1},
                             {"normal_offset", options.normalOffset},
                             {"boundary_radius", options.boundaryRadius},
                             {"frames", std::move(frames[e])},
                             {"totals", std::move(totalsJson)},
                             {"machine", machine},
                             {"commit", commit},
                             {"created", utcNow()}};
    writeFileAtomically(options.out / (viewSlug(entries[e].label) + ".json"),
                        record.dump(1) + "\n");
    records.push_back(std::move(record));
  }
  return records;
}

}  // namespace sb

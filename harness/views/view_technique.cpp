#include "harness/views/view_technique.h"

#include <algorithm>
#include <limits>
#include <stdexcept>

#include <fmt/format.h>
#include <tbb/parallel_for.h>

#include "harness/views/cascaded_shadow_maps.h"
#include "harness/views/irregular_adaptive_shadow_maps.h"

namespace sb {

ViewDepthRange viewDepthRange(const GroundTruth& surface) {
  ViewDepthRange range{false, std::numeric_limits<double>::infinity(), 0};
  for (size_t p = 0; p < surface.covered.size(); ++p)
    if (surface.covered[p]) {
      range.any = true;
      range.nearest = std::min(range.nearest, double(surface.viewDepth[p]));
      range.farthest = std::max(range.farthest, double(surface.viewDepth[p]));
    }
  if (!range.any) range.nearest = 0;
  // A frame of one depth still needs a slice of some thickness.
  range.farthest = std::max(range.farthest, range.nearest * (1 + 1e-6) + 1e-9);
  range.nearest = std::max(range.nearest, range.farthest * 1e-6);
  return range;
}

const std::vector<ViewTechniqueRow>& viewTechniques() {
  static const std::vector<ViewTechniqueRow> rows = {csmRow(), iasmRow()};
  return rows;
}

const ViewTechniqueRow& findViewTechnique(std::string_view name) {
  for (const ViewTechniqueRow& row : viewTechniques())
    if (row.name == name) return row;
  std::string known;
  for (const ViewTechniqueRow& row : viewTechniques())
    known += (known.empty() ? "" : ", ") + row.name;
  throw std::invalid_argument(
      fmt::format("unknown view technique '{}' (known: {}; saved structures are given with "
                  "--structure)",
                  name, known));
}

namespace {

class StructureTechnique : public ViewTechnique {
 public:
  StructureTechnique(const Light& light, const Decoder& decoder, uint32_t resolution,
                     uint64_t bytes, int k, double offsetTexels)
      : light_(light),
        decoder_(decoder),
        bytes_(bytes),
        k_(k),
        offset_(offsetTexels * light.worldPerUnitWidth() / resolution) {}

  void prepare(const Camera&, const GroundTruth&) override {}

  void shade(const Camera&, const GroundTruth& surface, std::vector<float>& visibility) override {
    visibility.assign(surface.covered.size(), 0.0f);
    constexpr size_t kBatch = 4096;  // one decoder call per batch of pixels, never per pixel
    tbb::parallel_for(size_t(0), (surface.covered.size() + kBatch - 1) / kBatch, [&](size_t b) {
      std::vector<Query> queries;
      std::vector<size_t> pixels;
      for (size_t p = b * kBatch; p < std::min(surface.covered.size(), (b + 1) * kBatch); ++p) {
        if (!surface.covered[p]) continue;
        const glm::dvec3 q = light_.toLightSpace(glm::dvec3(surface.position[p]) +
                                                 offset_ * glm::dvec3(surface.normal[p]));
        if (!(q.x >= 0 && q.x < 1 && q.y >= 0 && q.y < 1)) {
          visibility[p] = 1.0f;  // outside the map: no caster
          continue;
        }
        queries.push_back({float(q.x), float(q.y), float(std::clamp(q.z, 0.0, 1.0))});
        pixels.push_back(p);
      }
      std::vector<float> answers(queries.size());
      decoder_.lookup(queries, k_, answers);
      for (size_t i = 0; i < pixels.size(); ++i) visibility[pixels[i]] = answers[i];
    });
  }

  uint64_t memoryBytes() const override { return bytes_; }

 private:
  Light light_;
  const Decoder& decoder_;
  uint64_t bytes_;
  int k_;
  double offset_;  // world units
};

}  // namespace

std::unique_ptr<ViewTechnique> makeStructureTechnique(const Light& light, const Decoder& decoder,
                                                      uint32_t resolution, uint64_t bytes, int k,
                                                      double offsetTexels) {
  return std::make_unique<StructureTechnique>(light, decoder, resolution, bytes, k, offsetTexels);
}

}  // namespace sb

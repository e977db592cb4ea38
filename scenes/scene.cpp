// Scene queries, the generator registry and openScene's specification grammar.
#include "scenes/scene.h"

#include <algorithm>
#include <array>
#include <bit>
#include <cctype>
#include <charconv>
#include <cmath>
#include <fstream>
#include <limits>
#include <memory>
#include <optional>
#include <system_error>
#include <unordered_set>

#include <fmt/format.h>
#include <nlohmann/json.hpp>
#define XXH_STATIC_LINKING_ONLY  // XXH3_state_t on the stack
#include <xxhash.h>

#include "scenes/detail.h"
#include "scenes/memory.h"

namespace sb {

uint64_t Scene::triangleCount() const {
  uint64_t count = 0;
  for (const Mesh& mesh : meshes) count += mesh.triangles.size();
  return count;
}

Bounds Scene::bounds() const {
  glm::vec3 lo{std::numeric_limits<float>::infinity()}, hi{-std::numeric_limits<float>::infinity()};
  for (const Mesh& mesh : meshes)
    for (const glm::uvec3& triangle : mesh.triangles)
      for (int corner = 0; corner < 3; ++corner) {
        const glm::vec3 p = mesh.vertices[triangle[corner]];
        lo = glm::min(lo, p);
        hi = glm::max(hi, p);
      }
  if (!(lo.x <= hi.x)) return {};  // no triangles
  return {lo, hi};
}

namespace {

// Feeds XXH3 with explicit little-endian bytes, buffered, so that the hash depends on the
// values alone: not on struct padding, alignment or the machine's byte order.
class HashStream {
 public:
  HashStream() { XXH3_64bits_reset(&state_); }
  void u8(uint8_t v) { put(&v, 1); }
  void u32(uint32_t v) {
    uint8_t bytes[4];
    for (int i = 0; i < 4; ++i) bytes[i] = static_cast<uint8_t>(v >> (8 * i));
    put(bytes, 4);
  }
  void u64(uint64_t v) {
    u32(static_cast<uint32_t>(v));
    u32(static_cast<uint32_t>(v >> 32));
  }
  void f32(float v) { u32(std::bit_cast<uint32_t>(v)); }
  void text(std::string_view s) {
    u64(s.size());
    put(s.data(), s.size());
  }
  uint64_t digest() {
    flush();
    return XXH3_64bits_digest(&state_);
  }

 private:
  void put(const void* data, size_t size) {
    if (used_ + size > buffer_.size()) flush();
    if (size > buffer_.size()) {
      XXH3_64bits_update(&state_, data, size);
      return;
    }
    std::copy_n(static_cast<const uint8_t*>(data), size, buffer_.data() + used_);
    used_ += size;
  }
  void flush() {
    XXH3_64bits_update(&state_, buffer_.data(), used_);
    used_ = 0;
  }

  XXH3_state_t state_;
  std::array<uint8_t, 1 << 16> buffer_;
  size_t used_ = 0;
};

}  // namespace

// Byte stream: mesh count, then per mesh: name (length, bytes), closed (1 byte), vertex count,
// vertices (x, y, z as float bits), triangle count, triangles (3 × uint32); integers in
// little-endian. Lengths are included so that no two different scenes share a stream.
std::string Scene::hash() const {
  auto stream = std::make_unique<HashStream>();  // 64 KiB buffer: keep it off the stack
  stream->u64(meshes.size());
  for (const Mesh& mesh : meshes) {
    stream->text(mesh.name);
    stream->u8(mesh.closed ? 1 : 0);
    stream->u64(mesh.vertices.size());
    for (const glm::vec3& v : mesh.vertices) {
      stream->f32(v.x);
      stream->f32(v.y);
      stream->f32(v.z);
    }
    stream->u64(mesh.triangles.size());
    for (const glm::uvec3& t : mesh.triangles) {
      stream->u32(t.x);
      stream->u32(t.y);
      stream->u32(t.z);
    }
  }
  return fmt::format("{:016x}", stream->digest());
}

LightSpec defaultLight() {
  LightSpec light;
  light.kind = LightKind::Directional;
  light.direction = glm::normalize(glm::vec3{0.35f, 0.25f, -1.0f});
  return light;
}

namespace {

// A generator of a size and a seed alone.
template <Scene (*Generate)(uint32_t, uint64_t), SceneFootprint (*Footprint)(uint32_t)>
GeneratorInfo withoutStyle(GeneratorInfo info) {
  info.generate = [name = info.name](const GeneratorKnobs& knobs) {
    detail::checkStyleKnobs(name, knobs, {});
    return Generate(knobs.size, knobs.seed);
  };
  info.footprint = [name = info.name](const GeneratorKnobs& knobs) {
    detail::checkStyleKnobs(name, knobs, {});
    return Footprint(knobs.size);
  };
  return info;
}

}  // namespace

const std::vector<GeneratorInfo>& sceneGenerators() {
  static const std::vector<GeneratorInfo> generators = {
      {.name = "city",
       .description =
           "closed city: box buildings with setbacks and spires on a ground slab; size = "
           "blocks per side",
       .defaultSize = 6,
       .fullSize = 36,
       .styleKnobs = detail::cityStyleKnobs(),
       .presets = detail::cityPresets(),
       .generate = detail::generateCity,
       .footprint = detail::cityFootprint},
      withoutStyle<detail::generateTerrain, detail::terrainFootprint>(
          {.name = "terrain",
           .description = "closed fractal landscape solid; size = grid cells per side",
           .defaultSize = 128,
           .fullSize = 1024}),
      withoutStyle<detail::generateForest, detail::forestFootprint>(
          {.name = "forest",
           .description = "open trees: tube trunks and branches, leaf cards, ground quad; size = "
                          "trees per side",
           .defaultSize = 8,
           .fullSize = 45}),
      {.name = "tangle",
       .description =
           "dense knot of closed tubes in a ball (hairball stand-in); size = number of tubes",
       .defaultSize = 12,
       .fullSize = 650,
       .styleKnobs = detail::tangleStyleKnobs(),
       .presets = detail::tanglePresets(),
       .generate = detail::generateTangle,
       .footprint = detail::tangleFootprint},
  };
  return generators;
}

namespace detail {

void checkSize(std::string_view generator, uint32_t size, uint32_t min, uint32_t max) {
  if (size < min || size > max)
    throw SceneError(
        fmt::format("generator '{}': size {} out of range [{}, {}]", generator, size, min, max));
}

void checkStyleKnobs(std::string_view generator, const GeneratorKnobs& knobs,
                     std::span<const StyleKnob> styleKnobs) {
  if (knobs.style.size() > styleKnobs.size())
    throw SceneError(fmt::format("generator '{}': {} style knobs given, it has {}", generator,
                                 knobs.style.size(), styleKnobs.size()));
  for (size_t k = 0; k < knobs.style.size(); ++k)
    if (knobs.style[k] > styleKnobs[k].max)
      throw SceneError(fmt::format("generator '{}': {} {} out of range [0, {}]", generator,
                                   styleKnobs[k].name, knobs.style[k], styleKnobs[k].max));
}

std::string generatedSceneName(std::string_view generator, const GeneratorKnobs& knobs,
                               std::span<const StyleKnob> styleKnobs) {
  std::string name = fmt::format("{}:size={},seed={}", generator, knobs.size, knobs.seed);
  for (size_t k = 0; k < styleKnobs.size(); ++k)
    if (knobs.styleKnob(k) != 0)
      name += fmt::format(",{}={}", styleKnobs[k].name, knobs.styleKnob(k));
  return name;
}

bool isValidMeshName(std::string_view name) {
  return !name.empty() && std::all_of(name.begin(), name.end(), [](char c) {
    return (c >= 'A' && c <= 'Z') || (c >= 'a' && c <= 'z') || (c >= '0' && c <= '9') || c == '_' ||
           c == '-';
  });
}

void validateScene(const Scene& scene, std::string_view origin) {
  auto fail = [&](const std::string& problem) {
    throw SceneError(fmt::format("scene '{}': {}", origin, problem));
  };
  if (scene.lights.empty()) fail("no lights");
  for (size_t l = 0; l < scene.lights.size(); ++l) {
    const LightSpec& light = scene.lights[l];
    if (light.kind == LightKind::Spot && !isValidSpotFov(light.fovDegrees))
      fail(fmt::format("light {}: spot fov {} degrees outside the accepted range (0, {})", l,
                       light.fovDegrees, kMaxSpotFovDegrees));
  }
  std::unordered_set<std::string_view> names;
  for (const Mesh& mesh : scene.meshes) {
    if (!isValidMeshName(mesh.name))
      fail(fmt::format("mesh name '{}' is not [A-Za-z0-9_-]+", mesh.name));
    if (!names.insert(mesh.name).second) fail(fmt::format("two meshes are named '{}'", mesh.name));
    for (const glm::vec3& v : mesh.vertices)
      if (!std::isfinite(v.x) || !std::isfinite(v.y) || !std::isfinite(v.z))
        fail(fmt::format("mesh '{}': non-finite vertex coordinate", mesh.name));
    for (const glm::uvec3& t : mesh.triangles)
      if (std::max({t.x, t.y, t.z}) >= mesh.vertices.size())
        fail(fmt::format("mesh '{}': vertex index {} out of range ({} vertices)", mesh.name,
                         std::max({t.x, t.y, t.z}), mesh.vertices.size()));
  }
  if (scene.triangleCount() == 0) fail("no triangles");
}

}  // namespace detail

namespace {

const GeneratorInfo* findGenerator(std::string_view name) {
  for (const GeneratorInfo& g : sceneGenerators())
    if (g.name == name) return &g;
  return nullptr;
}

std::string generatorNames() {
  std::string names;
  for (const GeneratorInfo& g : sceneGenerators()) names += (names.empty() ? "" : ", ") + g.name;
  return names;
}

std::optional<uint64_t> parseUnsigned(std::string_view text) {
  uint64_t value = 0;
  const auto [end, error] = std::from_chars(text.data(), text.data() + text.size(), value);
  if (error != std::errc{} || end != text.data() + text.size()) return std::nullopt;
  return value;
}

// "full" | a preset's name | "size=N" | "seed=N" | "<style knob>=N", comma-separated; each knob
// set at most once (full sets the size, a preset the size, the seed and the style knobs).
Scene openGenerator(const GeneratorInfo& generator, std::string_view spec, std::string_view knobs,
                    uint64_t memoryLimitBytes) {
  auto fail = [&](const std::string& problem) {
    std::string names = "size=N, seed=N, full";
    for (const StyleKnob& knob : generator.styleKnobs) names += ", " + knob.name + "=N";
    for (const GeneratorPreset& preset : generator.presets) names += ", " + preset.name;
    throw SceneError(fmt::format("scene '{}': {} (knobs of '{}': {}; e.g. '{}:size={},seed=7')",
                                 spec, problem, generator.name, names, generator.name,
                                 generator.defaultSize));
  };
  constexpr auto npos = std::string_view::npos;
  // size, seed, then the style knobs.
  std::vector<std::string_view> keys{"size", "seed"};
  for (const StyleKnob& knob : generator.styleKnobs) keys.push_back(knob.name);
  std::vector<std::optional<uint64_t>> values(keys.size());
  auto set = [&](size_t key, uint64_t value) {
    if (values[key]) fail(fmt::format("{} given twice", keys[key]));
    values[key] = value;
  };
  for (std::string_view rest = knobs; !rest.empty();) {
    const size_t comma = rest.find(',');
    const std::string_view knob = rest.substr(0, comma);
    rest = comma == npos ? std::string_view{} : rest.substr(comma + 1);
    if (comma != npos && rest.empty()) fail("trailing comma");
    if (knob == "full") {
      set(0, generator.fullSize);
      continue;
    }
    const auto preset = std::find_if(generator.presets.begin(), generator.presets.end(),
                                     [&](const GeneratorPreset& p) { return p.name == knob; });
    if (preset != generator.presets.end()) {
      set(0, preset->size);
      set(1, preset->seed);
      for (size_t k = 0; k < preset->style.size(); ++k) set(2 + k, preset->style[k]);
      continue;
    }
    const size_t equals = knob.find('=');
    const auto key = std::find(keys.begin(), keys.end(), knob.substr(0, equals));
    if (key == keys.end()) fail(fmt::format("unknown knob '{}'", knob));
    const std::optional<uint64_t> value =
        equals == npos ? std::nullopt : parseUnsigned(knob.substr(equals + 1));
    if (!value) fail(fmt::format("knob '{}' needs a non-negative integer value", knob));
    set(size_t(key - keys.begin()), *value);
  }
  for (size_t k = 0; k < keys.size(); ++k)  // all but the seed are 32-bit
    if (k != 1 && values[k] && *values[k] > std::numeric_limits<uint32_t>::max())
      fail(fmt::format("{} {} is too large", keys[k], *values[k]));
  GeneratorKnobs chosen{
      static_cast<uint32_t>(values[0].value_or(generator.defaultSize)), values[1].value_or(1), {}};
  for (size_t k = 2; k < keys.size(); ++k)
    chosen.style.push_back(static_cast<uint32_t>(values[k].value_or(0)));
  // The generator's own errors name the generator; the spec is put before them.
  auto namingSpec = [&](auto&& call) {
    try {
      return call();
    } catch (const SceneError& e) {
      throw SceneError(fmt::format("scene '{}': {}", spec, e.what()));
    }
  };
  const SceneFootprint footprint = namingSpec([&] { return generator.footprint(chosen); });
  detail::checkFitsInMemory(fmt::format("scene '{}'", spec),
                            fmt::format("generating up to {} triangles", footprint.triangles),
                            footprint.bytes, memoryLimitBytes, "choose a smaller size");
  Scene scene = namingSpec([&] { return generator.generate(chosen); });
  detail::validateScene(scene, spec);
  return scene;
}

bool hasJsonExtension(const std::filesystem::path& path) {
  std::string ext = path.extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(),
                 [](unsigned char c) { return std::tolower(c); });
  return ext == ".json";
}

// A model file's specification: the path, and whether its meshes are closed (a last
// ":closed" or ":open"; anything else after a ':' belongs to the path).
struct ModelSpec {
  std::string_view path;
  bool closed = false;
  bool closednessGiven = false;
};

ModelSpec modelSpec(std::string_view spec) {
  const size_t colon = spec.rfind(':');
  if (colon == std::string_view::npos) return {spec};
  const std::string_view word = spec.substr(colon + 1);
  if (word != "closed" && word != "open") return {spec};
  return {spec.substr(0, colon), word == "closed", true};
}

}  // namespace

Scene openScene(std::string_view spec) {
  const uint64_t available = detail::availableMemoryBytes();
  return openScene(spec, available > 0 ? available : std::numeric_limits<uint64_t>::max());
}

Scene openScene(std::string_view spec, uint64_t memoryLimitBytes) {
  if (spec.empty())
    throw SceneError("scene '': empty specification (a generator name such as 'city', or a file)");
  const size_t colon = spec.find(':');
  const std::string_view head = spec.substr(0, colon);
  if (const GeneratorInfo* generator = findGenerator(head))
    return openGenerator(
        *generator, spec,
        colon == std::string_view::npos ? std::string_view{} : spec.substr(colon + 1),
        memoryLimitBytes);

  const ModelSpec model = modelSpec(spec);
  const std::filesystem::path path{model.path};
  std::error_code error;
  if (!std::filesystem::exists(path, error)) {
    const bool looksLikeFile = head.find_first_of("./\\") != std::string_view::npos;
    if (!looksLikeFile)
      throw SceneError(
          fmt::format("scene '{}': no generator '{}' and no such file (generators: {})", spec, head,
                      generatorNames()));
    throw SceneError(fmt::format("scene '{}': no such file", spec));
  }
  if (!hasJsonExtension(path)) return detail::loadModelScene(path, model.closed, memoryLimitBytes);
  if (model.closednessGiven)
    throw SceneError(
        fmt::format("scene '{}': ':closed' and ':open' apply to model files; a scene file says "
                    "\"closed\" per mesh",
                    spec));
  return loadSceneFile(path, memoryLimitBytes);
}

std::vector<std::filesystem::path> sceneSourceFiles(std::string_view spec) {
  namespace fs = std::filesystem;
  const fs::path named{std::string(modelSpec(spec).path)};
  std::error_code error;
  if (!fs::is_regular_file(named, error)) return {};
  std::vector<fs::path> files{named};
  if (!hasJsonExtension(named)) return files;
  std::ifstream in(named);
  const nlohmann::json scene = nlohmann::json::parse(in, nullptr, false);
  if (!scene.is_object() || !scene.contains("meshes") || !scene["meshes"].is_array()) return files;
  for (const nlohmann::json& mesh : scene["meshes"])
    if (mesh.is_object() && mesh.contains("file") && mesh["file"].is_string()) {
      const fs::path model{mesh["file"].get<std::string>()};
      files.push_back(model.is_absolute() ? model : named.parent_path() / model);
    }
  return files;
}

}  // namespace sb

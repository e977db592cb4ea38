// Scene files (JSON: meshes, transforms, closedness, lights) and model files read by Assimp.
//
// Every problem becomes one SceneError line that names the file and, inside a scene file, the
// JSON path of the offending value ("meshes[1].transform.rotate.axis"), so that a typo is found
// without a debugger. Unknown keys are errors too: a misspelt "tranform" would otherwise be
// silently ignored and the scene would measure different geometry than its author meant.
#include <algorithm>
#include <cmath>
#include <fstream>
#include <initializer_list>
#include <iterator>
#include <limits>
#include <set>
#include <span>
#include <string>
#include <vector>

#include <assimp/config.h>
#include <assimp/postprocess.h>
#include <assimp/scene.h>
#include <fmt/format.h>
#include <assimp/Importer.hpp>
#include <nlohmann/json.hpp>

#include "scenes/det_math.h"
#include "scenes/detail.h"
#include "scenes/memory.h"
#include "scenes/mesh_builder.h"
#include "scenes/model_header.h"

namespace sb {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

// Foreign messages (Assimp, the JSON parser) may span lines; a SceneError is one line.
std::string oneLine(std::string text) {
  std::replace_if(
      text.begin(), text.end(), [](char c) { return c == '\n' || c == '\r'; }, ' ');
  while (!text.empty() && text.back() == ' ') text.pop_back();
  return text;
}

// Checks that `path` is an existing, regular, non-empty file, with messages of our own: the
// libraries' messages for these cases are vague ("No suitable reader found").
void checkFile(const fs::path& path, const std::string& prefix) {
  std::error_code error;
  if (!fs::exists(path, error)) throw SceneError(prefix + ": no such file");
  if (!fs::is_regular_file(path, error)) throw SceneError(prefix + ": not a regular file");
  if (fs::file_size(path, error) == 0 && !error) throw SceneError(prefix + ": empty file");
}

std::string readFile(const fs::path& path, const std::string& prefix) {
  checkFile(path, prefix);
  std::ifstream in(path, std::ios::binary);
  if (!in) throw SceneError(prefix + ": cannot open the file");
  std::string text{std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
  if (in.bad()) throw SceneError(prefix + ": cannot read the file");
  if (text.empty()) throw SceneError(prefix + ": empty file");
  return text;
}

// ---------------------------------------------------------------------------------------------
// Model files

std::string sanitisedName(std::string_view raw) {
  std::string name;
  for (char c : raw) name += detail::isValidMeshName(std::string_view(&c, 1)) ? c : '_';
  return name.empty() ? "mesh" : name;
}

// `name`, or `name_2`, `name_3`, … whichever is still free.
std::string uniqueName(const std::string& name, std::set<std::string>& taken) {
  std::string candidate = name;
  for (int suffix = 2; !taken.insert(candidate).second; ++suffix)
    candidate = fmt::format("{}_{}", name, suffix);
  return candidate;
}

// Assimp 5.2's TriangulateProcess aborts the process (an ai_assert) on a face without indices,
// which its validation lets through and its PLY reader makes of a zero-length or misread face
// line (fuzz/regressions/model_file/). Checked before any post-processing runs.
void checkFacesHaveIndices(const aiScene& model, const std::string& prefix) {
  for (unsigned m = 0; m < model.mNumMeshes; ++m)
    for (unsigned f = 0; f < model.mMeshes[m]->mNumFaces; ++f)
      if (model.mMeshes[m]->mFaces[f].mNumIndices == 0)
        throw SceneError(fmt::format("{}: mesh {}: face {} has no vertex index", prefix, m, f));
}

// One open mesh per model mesh that has triangles; `prefix` starts every error message.
std::vector<Mesh> readModel(const fs::path& path, const std::string& prefix,
                            uint64_t memoryLimitBytes) {
  checkFile(path, prefix);
  std::error_code error;
  const uint64_t fileSize = fs::file_size(path, error);
  if (error) throw SceneError(prefix + ": cannot read the file's size: " + error.message());
  if (const auto footprint = detail::declaredFootprint(path, fileSize, prefix))
    detail::checkFitsInMemory(
        prefix,
        fmt::format("reading the {} vertices and {} faces its header declares", footprint->vertices,
                    footprint->triangles),
        footprint->bytes, memoryLimitBytes, "use a smaller model");
  Assimp::Importer importer;
  // Without this, PreTransformVertices joins meshes that share a material, and their names.
  importer.SetPropertyBool(AI_CONFIG_PP_PTV_KEEP_HIERARCHY, true);
  const aiScene* model = importer.ReadFile(path.string(), aiProcess_ValidateDataStructure);
  if (!model)
    throw SceneError(
        fmt::format("{}: cannot read the model: {}", prefix, oneLine(importer.GetErrorString())));
  checkFacesHaveIndices(*model, prefix);
  model = importer.ApplyPostProcessing(aiProcess_Triangulate | aiProcess_JoinIdenticalVertices |
                                       aiProcess_PreTransformVertices);
  if (!model)
    throw SceneError(fmt::format("{}: cannot post-process the model: {}", prefix,
                                 oneLine(importer.GetErrorString())));

  std::vector<Mesh> meshes;
  std::set<std::string> taken;
  uint64_t linesOrPoints = 0;
  for (unsigned m = 0; m < model->mNumMeshes; ++m) {
    const aiMesh& in = *model->mMeshes[m];
    Mesh mesh;
    for (unsigned f = 0; f < in.mNumFaces; ++f) {
      const aiFace& face = in.mFaces[f];
      if (face.mNumIndices != 3) {
        ++linesOrPoints;  // Triangulate leaves only points, lines and triangles
        continue;
      }
      for (unsigned k = 0; k < 3; ++k)
        if (face.mIndices[k] >= in.mNumVertices)
          throw SceneError(fmt::format("{}: mesh {}: vertex index {} out of range ({} vertices)",
                                       prefix, m, face.mIndices[k], in.mNumVertices));
      mesh.triangles.push_back({face.mIndices[0], face.mIndices[1], face.mIndices[2]});
    }
    if (mesh.triangles.empty()) continue;
    mesh.vertices.reserve(in.mNumVertices);
    for (unsigned v = 0; v < in.mNumVertices; ++v) {
      const aiVector3D& p = in.mVertices[v];
      if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z))
        throw SceneError(fmt::format("{}: mesh {}: non-finite vertex coordinate", prefix, m));
      mesh.vertices.push_back({p.x, p.y, p.z});
    }
    mesh.name = uniqueName(sanitisedName(in.mName.C_Str()), taken);
    meshes.push_back(std::move(mesh));
  }
  if (meshes.empty())
    throw SceneError(prefix + (linesOrPoints > 0
                                   ? ": no triangles (the file holds only lines or points)"
                                   : ": no triangles (the file holds no meshes)"));
  return meshes;
}

// Concatenates meshes into one, offsetting indices.
Mesh merge(std::vector<Mesh> parts) {
  Mesh merged;
  for (const Mesh& part : parts) {
    const auto offset = static_cast<uint32_t>(merged.vertices.size());
    merged.vertices.insert(merged.vertices.end(), part.vertices.begin(), part.vertices.end());
    for (const glm::uvec3& t : part.triangles) merged.triangles.push_back(t + offset);
  }
  return merged;
}

// ---------------------------------------------------------------------------------------------
// Reading JSON values, each with the path of the value for messages

class JsonReader {
 public:
  JsonReader(std::string origin, fs::path folder, uint64_t memoryLimitBytes)
      : origin_(std::move(origin)),
        folder_(std::move(folder)),
        memoryLimitBytes_(memoryLimitBytes) {}

  [[noreturn]] void fail(std::string_view where, std::string_view problem) const {
    throw SceneError(fmt::format("scene '{}': {}: {}", origin_, where, problem));
  }
  const std::string& origin() const { return origin_; }
  const fs::path& folder() const { return folder_; }
  // What the scene's models and generators may take at most, each checked before it is read.
  uint64_t memoryLimitBytes() const { return memoryLimitBytes_; }

  // An object whose keys are all among `allowed`.
  void object(const json& value, std::string_view where,
              std::initializer_list<std::string_view> allowed) const {
    object(value, where, std::span(allowed.begin(), allowed.end()));
  }
  void object(const json& value, std::string_view where,
              std::span<const std::string_view> allowed) const {
    if (!value.is_object()) fail(where, "expected an object");
    for (const auto& item : value.items())
      if (std::find(allowed.begin(), allowed.end(), item.key()) == allowed.end())
        fail(where,
             fmt::format("unknown key '{}' (valid: {})", item.key(), fmt::join(allowed, ", ")));
  }

  double number(const json& value, std::string_view where) const {
    if (!value.is_number()) fail(where, "expected a number");
    const double x = value.get<double>();
    if (!std::isfinite(x) || std::abs(x) > std::numeric_limits<float>::max())
      fail(where, "number out of range");
    return x;
  }

  uint64_t count(const json& value, std::string_view where) const {
    if (!value.is_number_unsigned()) fail(where, "expected a non-negative integer");
    return value.get<uint64_t>();
  }

  bool boolean(const json& value, std::string_view where) const {
    if (!value.is_boolean()) fail(where, "expected true or false");
    return value.get<bool>();
  }

  std::string string(const json& value, std::string_view where) const {
    if (!value.is_string()) fail(where, "expected a string");
    return value.get<std::string>();
  }

  const json& array(const json& value, std::string_view where, size_t size = 0) const {
    if (!value.is_array()) fail(where, "expected an array");
    if (size > 0 && value.size() != size)
      fail(where, fmt::format("expected an array of {} elements", size));
    return value;
  }

  glm::dvec3 vec3(const json& value, std::string_view where) const {
    array(value, where, 3);
    glm::dvec3 v;
    for (int k = 0; k < 3; ++k) v[k] = number(value[k], fmt::format("{}[{}]", where, k));
    return v;
  }

  glm::dvec3 direction(const json& value, std::string_view where) const {
    const glm::dvec3 d = vec3(value, where);
    if (glm::dot(d, d) == 0.0) fail(where, "direction must not be zero");
    return glm::normalize(d);
  }

 private:
  std::string origin_;
  fs::path folder_;
  uint64_t memoryLimitBytes_;
};

const json* member(const json& object, const char* key) {
  const auto it = object.find(key);
  return it == object.end() ? nullptr : &*it;
}

std::string at(std::string_view where, std::string_view key) {
  return fmt::format("{}.{}", where, key);
}

// ---------------------------------------------------------------------------------------------
// Transforms

// Rotation by `degrees` about `axis` (Rodrigues), without libm so that scene bytes match on
// every machine; whole turns are removed exactly first (fmod is exact).
glm::dmat4 rotation(glm::dvec3 axis, double degrees) {
  const glm::dvec2 sc = detail::portableSinCos(std::fmod(degrees, 360.0) * detail::kPi / 180.0);
  const double s = sc.x, c = sc.y, t = 1.0 - c;
  const glm::dvec3 a = axis;
  glm::dmat4 r(1.0);  // column-major: r[column][row]
  r[0] = {t * a.x * a.x + c, t * a.x * a.y + s * a.z, t * a.x * a.z - s * a.y, 0};
  r[1] = {t * a.x * a.y - s * a.z, t * a.y * a.y + c, t * a.y * a.z + s * a.x, 0};
  r[2] = {t * a.x * a.z + s * a.y, t * a.y * a.z - s * a.x, t * a.z * a.z + c, 0};
  return r;
}

// {"translate": [3], "scale": number or [3], "rotate": {"axis": [3], "degrees": x}}, applied as
// scale, then rotate, then translate; or {"matrix": [16 numbers, row-major, affine]}.
glm::dmat4 readTransform(const JsonReader& in, const json& value, const std::string& where) {
  in.object(value, where, {"translate", "scale", "rotate", "matrix"});
  if (const json* matrix = member(value, "matrix")) {
    if (value.size() > 1) in.fail(where, "'matrix' excludes 'translate', 'scale' and 'rotate'");
    in.array(*matrix, at(where, "matrix"), 16);
    glm::dmat4 m;
    for (int row = 0; row < 4; ++row)
      for (int column = 0; column < 4; ++column)
        m[column][row] = in.number((*matrix)[row * 4 + column],
                                   fmt::format("{}.matrix[{}]", where, row * 4 + column));
    if (m[0][3] != 0.0 || m[1][3] != 0.0 || m[2][3] != 0.0 || m[3][3] != 1.0)
      in.fail(at(where, "matrix"), "the last row must be 0, 0, 0, 1");
    return m;
  }
  glm::dmat4 scale(1.0), rotate(1.0), translate(1.0);
  if (const json* s = member(value, "scale")) {
    const glm::dvec3 factors = s->is_number() ? glm::dvec3(in.number(*s, at(where, "scale")))
                                              : in.vec3(*s, at(where, "scale"));
    for (int k = 0; k < 3; ++k) scale[k][k] = factors[k];
  }
  if (const json* r = member(value, "rotate")) {
    const std::string rw = at(where, "rotate");
    in.object(*r, rw, {"axis", "degrees"});
    const json* axis = member(*r, "axis");
    const json* degrees = member(*r, "degrees");
    if (!axis || !degrees) in.fail(rw, "needs 'axis' and 'degrees'");
    rotate = rotation(in.direction(*axis, at(rw, "axis")), in.number(*degrees, at(rw, "degrees")));
  }
  if (const json* t = member(value, "translate"))
    translate[3] = glm::dvec4(in.vec3(*t, at(where, "translate")), 1.0);
  return translate * rotate * scale;
}

// Transforms in double, rounding once to float. A mirroring transform turns counter-clockwise
// faces clockwise, so their winding is reversed to keep normals pointing outward.
void applyTransform(Mesh& mesh, const glm::dmat4& m, const JsonReader& in,
                    const std::string& where) {
  const double det = glm::determinant(glm::dmat3(m));
  if (!(std::abs(det) > 0.0)) in.fail(where, "the transform is singular (it flattens the mesh)");
  for (glm::vec3& v : mesh.vertices) v = glm::vec3(m * glm::dvec4(glm::dvec3(v), 1.0));
  if (det < 0.0)
    for (glm::uvec3& t : mesh.triangles) std::swap(t.y, t.z);
}

// ---------------------------------------------------------------------------------------------
// Meshes and lights

Mesh readInlineMesh(const JsonReader& in, const json& value, const std::string& where) {
  const json* vertices = member(value, "vertices");
  const json* triangles = member(value, "triangles");
  if (!vertices || !triangles)
    in.fail(where, "inline geometry needs both 'vertices' and 'triangles'");
  Mesh mesh;
  in.array(*vertices, at(where, "vertices"));
  for (size_t v = 0; v < vertices->size(); ++v)
    mesh.vertices.push_back(
        glm::vec3(in.vec3((*vertices)[v], fmt::format("{}.vertices[{}]", where, v))));
  in.array(*triangles, at(where, "triangles"));
  for (size_t t = 0; t < triangles->size(); ++t) {
    const std::string tw = fmt::format("{}.triangles[{}]", where, t);
    const json& triangle = in.array((*triangles)[t], tw, 3);
    glm::uvec3 indices;
    for (int k = 0; k < 3; ++k) {
      const uint64_t index = in.count(triangle[k], fmt::format("{}[{}]", tw, k));
      if (index >= mesh.vertices.size())
        in.fail(tw, fmt::format("vertex index {} out of range ({} vertices)", index,
                                mesh.vertices.size()));
      indices[k] = static_cast<uint32_t>(index);
    }
    mesh.triangles.push_back(indices);
  }
  return mesh;
}

Mesh readBox(const JsonReader& in, const json& value, const std::string& where) {
  in.object(value, where, {"min", "max"});
  const json* lo = member(value, "min");
  const json* hi = member(value, "max");
  if (!lo || !hi) in.fail(where, "needs 'min' and 'max'");
  const glm::vec3 min(in.vec3(*lo, at(where, "min"))), max(in.vec3(*hi, at(where, "max")));
  if (!glm::all(glm::lessThan(min, max))) in.fail(where, "'min' must be below 'max' on every axis");
  Mesh mesh;
  detail::addBox(mesh, min, max);
  return mesh;
}

// All meshes of a generated scene as one; `closed` when every one of them is.
Mesh readGenerated(const JsonReader& in, const json& value, const std::string& where,
                   bool& closed) {
  const std::string name = in.string(*member(value, "generator"), at(where, "generator"));
  const auto& generators = sceneGenerators();
  const auto generator =
      std::find_if(generators.begin(), generators.end(), [&](auto& g) { return g.name == name; });
  if (generator == generators.end()) {
    std::vector<std::string> names;
    for (const GeneratorInfo& g : generators) names.push_back(g.name);
    in.fail(at(where, "generator"),
            fmt::format("unknown generator '{}' (valid: {})", name, fmt::join(names, ", ")));
  }
  uint64_t size = generator->defaultSize, seed = 1;
  if (const json* s = member(value, "size")) size = in.count(*s, at(where, "size"));
  if (const json* s = member(value, "seed")) seed = in.count(*s, at(where, "seed"));
  if (size > std::numeric_limits<uint32_t>::max()) in.fail(at(where, "size"), "too large");
  GeneratorKnobs knobs{static_cast<uint32_t>(size), seed, {}};
  // "style": {"relief": 40}, the generator's style knobs by name.
  if (const json* style = member(value, "style")) {
    const std::string styleWhere = at(where, "style");
    if (generator->styleKnobs.empty())
      in.fail(styleWhere, fmt::format("generator '{}' has no style knobs", name));
    std::vector<std::string_view> names;
    for (const StyleKnob& knob : generator->styleKnobs) names.push_back(knob.name);
    in.object(*style, styleWhere, names);
    for (const StyleKnob& knob : generator->styleKnobs) {
      const json* setting = member(*style, knob.name.c_str());
      const uint64_t chosen = setting ? in.count(*setting, at(styleWhere, knob.name)) : 0;
      if (chosen > knob.max)
        in.fail(at(styleWhere, knob.name),
                fmt::format("{} out of range [0, {}]", chosen, knob.max));
      knobs.style.push_back(static_cast<uint32_t>(chosen));
    }
  }
  Scene scene;
  try {
    // The generated meshes, then their merged copy.
    const SceneFootprint footprint = generator->footprint(knobs);
    detail::checkFitsInMemory(fmt::format("scene '{}': {}", in.origin(), where),
                              fmt::format("generating up to {} triangles", footprint.triangles),
                              footprint.bytes + footprint.vertices * sizeof(glm::vec3) +
                                  footprint.triangles * sizeof(glm::uvec3),
                              in.memoryLimitBytes(), "choose a smaller size");
    scene = generator->generate(knobs);
  } catch (const SceneError& e) {
    in.fail(where, e.what());
  }
  closed =
      std::all_of(scene.meshes.begin(), scene.meshes.end(), [](const Mesh& m) { return m.closed; });
  return merge(std::move(scene.meshes));
}

Mesh readMesh(const JsonReader& in, const json& value, size_t index) {
  const std::string where = fmt::format("meshes[{}]", index);
  in.object(value, where,
            {"name", "closed", "file", "vertices", "triangles", "box", "generator", "size", "seed",
             "style", "transform"});
  std::string name = fmt::format("mesh{}", index);
  if (const json* n = member(value, "name")) {
    name = in.string(*n, at(where, "name"));
    if (!detail::isValidMeshName(name))
      in.fail(at(where, "name"), fmt::format("'{}' is not [A-Za-z0-9_-]+", name));
  }

  const int sources = (member(value, "file") ? 1 : 0) + (member(value, "box") ? 1 : 0) +
                      (member(value, "generator") ? 1 : 0) +
                      (member(value, "vertices") || member(value, "triangles") ? 1 : 0);
  if (sources != 1)
    in.fail(where, "needs exactly one of 'file', 'vertices'+'triangles', 'box', 'generator'");
  if (!member(value, "generator") &&
      (member(value, "size") || member(value, "seed") || member(value, "style")))
    in.fail(where, "'size', 'seed' and 'style' belong to a 'generator' mesh");

  Mesh mesh;
  bool closedByDefault = false;
  if (const json* file = member(value, "file")) {
    const fs::path relative = in.string(*file, at(where, "file"));
    const fs::path path = relative.is_absolute() ? relative : in.folder() / relative;
    mesh = merge(readModel(
        path, fmt::format("scene '{}': {}: model '{}'", in.origin(), where, path.string()),
        in.memoryLimitBytes()));
  } else if (const json* box = member(value, "box")) {
    mesh = readBox(in, *box, at(where, "box"));
    closedByDefault = true;
  } else if (member(value, "generator")) {
    mesh = readGenerated(in, value, where, closedByDefault);
  } else {
    mesh = readInlineMesh(in, value, where);
  }
  mesh.name = name;
  mesh.closed = closedByDefault;
  if (const json* closed = member(value, "closed"))
    mesh.closed = in.boolean(*closed, at(where, "closed"));
  if (mesh.closed && member(value, "generator") && !closedByDefault)
    in.fail(at(where, "closed"), "the generator's meshes are open");
  // Boxes and closed generators are closed by construction; a model or inline geometry only by
  // its author's word, which is checked.
  if (mesh.closed && !closedByDefault)
    detail::checkClosedMesh(mesh, fmt::format("scene '{}': {}", in.origin(), where));
  if (const json* transform = member(value, "transform"))
    applyTransform(mesh, readTransform(in, *transform, at(where, "transform")), in,
                   at(where, "transform"));
  return mesh;
}

LightSpec readLight(const JsonReader& in, const json& value, size_t index) {
  const std::string where = fmt::format("lights[{}]", index);
  in.object(value, where, {"type", "direction", "position", "fov", "depth"});
  const json* type = member(value, "type");
  const json* direction = member(value, "direction");
  if (!type) in.fail(where, "needs a 'type' ('directional' or 'spot')");
  if (!direction) in.fail(where, "needs a 'direction'");
  LightSpec light;
  light.direction = glm::vec3(in.direction(*direction, at(where, "direction")));
  const std::string kind = in.string(*type, at(where, "type"));
  if (kind == "directional") {
    if (value.size() > 2) in.fail(where, "a directional light has only 'type' and 'direction'");
    light.kind = LightKind::Directional;
    return light;
  }
  if (kind != "spot")
    in.fail(at(where, "type"),
            fmt::format("unknown light type '{}' (valid: directional, spot)", kind));
  light.kind = LightKind::Spot;
  const json* position = member(value, "position");
  if (!position) in.fail(where, "a spot light needs a 'position'");
  light.position = glm::vec3(in.vec3(*position, at(where, "position")));
  if (const json* fov = member(value, "fov")) {
    // Checked as stored (a float): 179.99999999 is below 180 as a double but 180 as a float.
    light.fovDegrees = static_cast<float>(in.number(*fov, at(where, "fov")));
    if (!isValidSpotFov(light.fovDegrees))
      in.fail(at(where, "fov"), fmt::format("{} degrees is outside the accepted range (0, {})",
                                            light.fovDegrees, kMaxSpotFovDegrees));
  }
  if (const json* depth = member(value, "depth")) {
    const std::string d = in.string(*depth, at(where, "depth"));
    if (d == "linear")
      light.depth = DepthDistribution::Linear;
    else if (d == "log" || d == "logarithmic")
      light.depth = DepthDistribution::Logarithmic;
    else
      in.fail(at(where, "depth"),
              fmt::format("unknown depth distribution '{}' (valid: linear, log)", d));
  }
  return light;
}

Scene readScene(const JsonReader& in, const json& document, const fs::path& path) {
  in.object(document, "top level", {"name", "meshes", "lights"});
  Scene scene;
  scene.name = path.stem().string();
  if (const json* name = member(document, "name")) scene.name = in.string(*name, "name");
  const json* meshes = member(document, "meshes");
  if (!meshes) in.fail("top level", "needs 'meshes'");
  in.array(*meshes, "meshes");
  for (size_t m = 0; m < meshes->size(); ++m) scene.meshes.push_back(readMesh(in, (*meshes)[m], m));
  if (const json* lights = member(document, "lights")) {
    in.array(*lights, "lights");
    if (lights->empty()) in.fail("lights", "empty (leave 'lights' out for the default light)");
    for (size_t l = 0; l < lights->size(); ++l)
      scene.lights.push_back(readLight(in, (*lights)[l], l));
  } else {
    scene.lights = {defaultLight()};
  }
  return scene;
}

}  // namespace

Scene loadSceneFile(const std::filesystem::path& path) {
  const uint64_t available = detail::availableMemoryBytes();
  return loadSceneFile(path, available > 0 ? available : std::numeric_limits<uint64_t>::max());
}

Scene loadSceneFile(const std::filesystem::path& path, uint64_t memoryLimitBytes) {
  const std::string origin = path.string();
  try {
    const std::string text = readFile(path, fmt::format("scene '{}'", origin));
    json document;
    try {
      document = json::parse(text);
    } catch (const json::parse_error& e) {
      throw SceneError(fmt::format("scene '{}': invalid JSON: {}", origin, oneLine(e.what())));
    }
    Scene scene =
        readScene(JsonReader(origin, path.parent_path(), memoryLimitBytes), document, path);
    detail::validateScene(scene, origin);
    return scene;
  } catch (const SceneError&) {
    throw;
  } catch (const std::bad_alloc&) {
    throw;
  } catch (const std::exception& e) {
    // A library exception that the checks above did not foresee: still one SceneError.
    throw SceneError(fmt::format("scene '{}': {}", origin, oneLine(e.what())));
  }
}

namespace detail {

Scene loadModelScene(const std::filesystem::path& path, bool closed, uint64_t memoryLimitBytes) {
  const std::string origin = path.string();
  try {
    Scene scene;
    scene.name = path.stem().string();
    scene.meshes = readModel(path, fmt::format("scene '{}'", origin), memoryLimitBytes);
    for (Mesh& mesh : scene.meshes) {
      mesh.closed = closed;
      if (closed) checkClosedMesh(mesh, fmt::format("scene '{}:closed'", origin));
    }
    scene.lights = {defaultLight()};
    validateScene(scene, origin);
    return scene;
  } catch (const SceneError&) {
    throw;
  } catch (const std::bad_alloc&) {
    throw;
  } catch (const std::exception& e) {
    throw SceneError(fmt::format("scene '{}': {}", origin, oneLine(e.what())));
  }
}

}  // namespace detail
}  // namespace sb

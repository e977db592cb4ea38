#include "scenes/watertight.h"

#include <algorithm>
#include <array>
#include <bit>
#include <numeric>
#include <vector>

#include <fmt/format.h>

#include "scenes/detail.h"

namespace sb {
namespace {

// Per vertex, the id of its position: vertices at bitwise-equal positions (after -0 → +0)
// share an id. Sorting keeps the memory at a few words per vertex, which a hash map would not.
std::vector<uint32_t> positionIds(const Mesh& mesh) {
  struct Keyed {
    std::array<uint32_t, 3> position;
    uint32_t vertex;
  };
  std::vector<Keyed> keyed(mesh.vertices.size());
  for (size_t v = 0; v < keyed.size(); ++v) {
    const glm::vec3 p = mesh.vertices[v] + 0.0f;
    keyed[v] = {
        {std::bit_cast<uint32_t>(p.x), std::bit_cast<uint32_t>(p.y), std::bit_cast<uint32_t>(p.z)},
        static_cast<uint32_t>(v)};
  }
  std::sort(keyed.begin(), keyed.end(),
            [](const Keyed& a, const Keyed& b) { return a.position < b.position; });
  std::vector<uint32_t> id(keyed.size());
  uint32_t next = 0;
  for (size_t i = 0; i < keyed.size(); ++i) {
    if (i > 0 && keyed[i].position != keyed[i - 1].position) ++next;
    id[keyed[i].vertex] = next;
  }
  return id;
}

// An edge between positions a < b: a in the high half, b in the low half.
constexpr uint64_t edgeKey(uint32_t a, uint32_t b) {
  return uint64_t{a} << 32 | b;
}

}  // namespace

Watertightness checkWatertight(const Mesh& mesh) {
  const std::vector<uint32_t> id = positionIds(mesh);
  Watertightness result;
  // Each directed edge by its undirected key, in one list per direction: a watertight surface
  // has every key once in each list. Both sorted, one merge pass counts the edges.
  std::vector<uint64_t> upward, downward;  // run from the lower to the higher id, and back
  upward.reserve(mesh.triangles.size() * 3 / 2 + 1);
  downward.reserve(mesh.triangles.size() * 3 / 2 + 1);
  for (const glm::uvec3& t : mesh.triangles) {
    const uint32_t corner[3] = {id[t.x], id[t.y], id[t.z]};
    if (corner[0] == corner[1] || corner[1] == corner[2] || corner[2] == corner[0]) {
      ++result.degenerateTriangles;
      continue;
    }
    for (int k = 0; k < 3; ++k) {
      const uint32_t from = corner[k], to = corner[(k + 1) % 3];
      if (from < to)
        upward.push_back(edgeKey(from, to));
      else
        downward.push_back(edgeKey(to, from));
    }
  }
  std::sort(upward.begin(), upward.end());
  std::sort(downward.begin(), downward.end());
  auto up = upward.begin(), down = downward.begin();
  while (up != upward.end() || down != downward.end()) {
    const uint64_t key =
        down == downward.end() || (up != upward.end() && *up < *down) ? *up : *down;
    auto past = [key](uint64_t other) { return other != key; };
    const auto upEnd = std::find_if(up, upward.end(), past);
    const auto downEnd = std::find_if(down, downward.end(), past);
    const auto forward = static_cast<uint64_t>(upEnd - up);
    const auto backward = static_cast<uint64_t>(downEnd - down);
    up = upEnd;
    down = downEnd;
    ++result.edges;
    if (forward == 1 && backward == 1) continue;
    if (forward + backward == 1)
      ++result.boundaryEdges;
    else if (forward + backward == 2)
      ++result.misorientedEdges;
    else
      ++result.nonManifoldEdges;
  }
  return result;
}

std::string Watertightness::describe() const {
  std::string text =
      watertight() ? "watertight" : fmt::format("not watertight: {} open edges", openEdges());
  std::vector<std::string> kinds;
  if (boundaryEdges) kinds.push_back(fmt::format("{} on holes", boundaryEdges));
  if (misorientedEdges)
    kinds.push_back(fmt::format("{} between faces wound against each other", misorientedEdges));
  if (nonManifoldEdges) kinds.push_back(fmt::format("{} in more than two faces", nonManifoldEdges));
  if (!kinds.empty()) text += fmt::format(" ({})", fmt::join(kinds, ", "));
  if (degenerateTriangles) text += fmt::format("; {} triangles without area", degenerateTriangles);
  return text;
}

double enclosedVolume(const Mesh& mesh) {
  double volume = 0.0;
  for (const glm::uvec3& t : mesh.triangles) {
    const glm::dvec3 a = mesh.vertices[t.x], b = mesh.vertices[t.y], c = mesh.vertices[t.z];
    volume += glm::dot(a, glm::cross(b, c)) / 6.0;
  }
  return volume;
}

namespace detail {

void checkClosedMesh(const Mesh& mesh, std::string_view where) {
  const Watertightness w = checkWatertight(mesh);
  if (!w.watertight())
    throw SceneError(fmt::format("{}: mesh '{}' is declared closed but is {}; load it open", where,
                                 mesh.name, w.describe()));
  if (!(enclosedVolume(mesh) > 0.0))
    throw SceneError(fmt::format(
        "{}: mesh '{}' is declared closed but is wound inside out (enclosed volume {}); reverse "
        "its faces or load it open",
        where, mesh.name, enclosedVolume(mesh)));
}

}  // namespace detail

}  // namespace sb

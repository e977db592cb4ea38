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
  using Key = std::array<uint32_t, 3>;
  std::vector<Key> keys(mesh.vertices.size());
  for (size_t v = 0; v < keys.size(); ++v) {
    const glm::vec3 p = mesh.vertices[v] + 0.0f;
    keys[v] = {std::bit_cast<uint32_t>(p.x), std::bit_cast<uint32_t>(p.y),
               std::bit_cast<uint32_t>(p.z)};
  }
  std::vector<uint32_t> order(keys.size());
  std::iota(order.begin(), order.end(), 0u);
  std::sort(order.begin(), order.end(), [&](uint32_t a, uint32_t b) { return keys[a] < keys[b]; });
  std::vector<uint32_t> id(keys.size());
  uint32_t next = 0;
  for (size_t i = 0; i < order.size(); ++i) {
    if (i > 0 && keys[order[i]] != keys[order[i - 1]]) ++next;
    id[order[i]] = next;
  }
  return id;
}

constexpr uint64_t directed(uint32_t from, uint32_t to) {
  return uint64_t{from} << 32 | to;
}

}  // namespace

Watertightness checkWatertight(const Mesh& mesh) {
  const std::vector<uint32_t> id = positionIds(mesh);
  Watertightness result;
  std::vector<uint64_t> edges;
  edges.reserve(mesh.triangles.size() * 3);
  for (const glm::uvec3& t : mesh.triangles) {
    const uint32_t a = id[t.x], b = id[t.y], c = id[t.z];
    if (a == b || b == c || c == a) {
      ++result.degenerateTriangles;
      continue;
    }
    edges.insert(edges.end(), {directed(a, b), directed(b, c), directed(c, a)});
  }
  std::sort(edges.begin(), edges.end());
  auto countOf = [&](uint64_t edge) {
    const auto [lo, hi] = std::equal_range(edges.begin(), edges.end(), edge);
    return static_cast<uint64_t>(hi - lo);
  };
  for (auto run = edges.begin(); run != edges.end();) {
    const auto end = std::upper_bound(run, edges.end(), *run);
    const uint64_t forward = static_cast<uint64_t>(end - run);
    const auto from = static_cast<uint32_t>(*run >> 32), to = static_cast<uint32_t>(*run);
    const uint64_t backward = countOf(directed(to, from));
    run = end;
    // Each undirected edge once: from its lower-to-higher direction, or its only direction.
    if (from > to && backward > 0) continue;
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

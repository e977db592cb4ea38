#include "harness/scene_export.h"

#include <stdexcept>

#include <ImfChannelList.h>
#include <ImfFrameBuffer.h>
#include <ImfHeader.h>
#include <ImfOutputFile.h>
#include <fmt/format.h>

namespace sb {

void exportLightSpaceObj(const Scene& scene, const Light& light, std::ostream& out) {
  out << fmt::format("# shadowbench light-space export of '{}' ({} triangles)\n", scene.name,
                     scene.triangleCount());
  out << "# x, y in [0, 1) across the shadow map; z = depth in [0, 1] from the light\n";
  size_t base = 1;
  for (const Mesh& mesh : scene.meshes) {
    out << fmt::format("o {}_{}\n", mesh.closed ? "closed" : "open", mesh.name);
    for (const glm::vec3& v : mesh.vertices) {
      const glm::dvec3 p = light.toLightSpace(glm::dvec3(v));
      out << fmt::format("v {:.9g} {:.9g} {:.9g}\n", p.x, p.y, p.z);
    }
    for (const glm::uvec3& t : mesh.triangles)
      out << fmt::format("f {} {} {}\n", base + t.x, base + t.y, base + t.z);
    base += mesh.vertices.size();
  }
  if (!out) throw std::runtime_error("cannot write the OBJ export");
}

void writeDualDepthExr(const DepthSource& source, const std::filesystem::path& path) {
  const uint32_t r = source.resolution();
  if (r > kMaxExrResolution) throw std::invalid_argument("EXR output is limited to 16K² maps");
  std::vector<float> lo(size_t(r) * r), hi(size_t(r) * r);
  streamDualDepth(source, defaultTileSize(r), [&](const DualDepthTile& tile) {
    for (uint32_t row = 0; row < tile.height; ++row)
      for (uint32_t col = 0; col < tile.width; ++col) {
        const size_t at = size_t(tile.y0 + row) * r + tile.x0 + col;
        lo[at] = tile.lo[size_t(row) * tile.width + col];
        hi[at] = tile.hi[size_t(row) * tile.width + col];
      }
  });
  Imf::Header header{int(r), int(r)};
  header.channels().insert("lo", Imf::Channel(Imf::FLOAT));
  header.channels().insert("hi", Imf::Channel(Imf::FLOAT));
  Imf::FrameBuffer frame;
  frame.insert("lo", Imf::Slice(Imf::FLOAT, reinterpret_cast<char*>(lo.data()), sizeof(float),
                                sizeof(float) * r));
  frame.insert("hi", Imf::Slice(Imf::FLOAT, reinterpret_cast<char*>(hi.data()), sizeof(float),
                                sizeof(float) * r));
  Imf::OutputFile file(path.c_str(), header);
  file.setFrameBuffer(frame);
  file.writePixels(int(r));
}

}  // namespace sb

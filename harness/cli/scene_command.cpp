#include <memory>
#include <sstream>

#include <fmt/format.h>

#include "harness/cell.h"
#include "harness/cli/commands.h"
#include "harness/cli/options.h"
#include "harness/scene_export.h"
#include "scenes/watertight.h"
#include "schemes/interface/atomic_file.h"

namespace sb::cli {

namespace {

void listGenerators() {
  for (const GeneratorInfo& g : sceneGenerators()) {
    fmt::print("{:8} default size {}, full size {} — {}\n", g.name, g.defaultSize, g.fullSize,
               g.description);
    for (const StyleKnob& knob : g.styleKnobs)
      fmt::print("{:8}   {}=0…{}: {}\n", "", knob.name, knob.max, knob.description);
    for (const GeneratorPreset& preset : g.presets) {
      std::string knobs = fmt::format("size={},seed={}", preset.size, preset.seed);
      for (size_t k = 0; k < preset.style.size(); ++k)
        knobs += fmt::format(",{}={}", g.styleKnobs[k].name, preset.style[k]);
      fmt::print("{:8}   {}:{} ({}): fitted to {}\n", "", g.name, preset.name, knobs,
                 preset.fittedTo);
    }
  }
}

void printSceneInfo(const MapOptions& o) {
  const Scene scene = openScene(o.scene);
  const Bounds b = scene.bounds();
  fmt::print("scene {}: {} triangles in {} meshes, hash {}\n", scene.name, scene.triangleCount(),
             scene.meshes.size(), scene.hash());
  fmt::print("bounds ({}, {}, {}) – ({}, {}, {})\n", b.min.x, b.min.y, b.min.z, b.max.x, b.max.y,
             b.max.z);
  for (const Mesh& m : scene.meshes)
    fmt::print("  {:24} {:6} {:>10} triangles, {}\n", m.name, m.closed ? "closed" : "open",
               m.triangles.size(), checkWatertight(m).describe());
  for (size_t i = 0; i < scene.lights.size(); ++i)
    fmt::print("  light {}: {}\n", i, sceneLight(scene, uint32_t(i)).describe().dump());
}

struct ExportOptions {
  MapOptions map;
  std::string output;
};

void exportScene(const ExportOptions& o) {
  checkOutputFile(o.output, sceneSourceFiles(o.map.scene));
  const Scene scene = openScene(o.map.scene);
  std::ostringstream obj;
  exportLightSpaceObj(scene, sceneLight(scene, o.map.light), obj);
  writeFileAtomically(o.output, obj.view());
  fmt::print("wrote {} ({} triangles in light space)\n", o.output, scene.triangleCount());
}

}  // namespace

void addSceneCommand(CLI::App& app) {
  CLI::App* scene = app.add_subcommand("scene", "inspect and export scenes");
  scene->require_subcommand(1);
  scene->add_subcommand("list", "list the procedural generators")->callback(listGenerators);

  auto info = std::make_shared<MapOptions>();
  CLI::App* infoCmd =
      scene->add_subcommand("info", "triangles, meshes, closedness, bounds, lights, hash");
  info->addTo(infoCmd, false);
  infoCmd->callback([info] { printSceneInfo(*info); });

  auto exported = std::make_shared<ExportOptions>();
  CLI::App* exportCmd = scene->add_subcommand("export", "write the scene in light space as OBJ");
  exported->map.addTo(exportCmd, false);
  exportCmd->add_option("--output,-o", exported->output, "OBJ file to write")->required();
  exportCmd->callback([exported] { exportScene(*exported); });
}

}  // namespace sb::cli

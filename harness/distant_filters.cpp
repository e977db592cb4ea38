#include "harness/distant_filters.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <filesystem>
#include <map>
#include <memory>
#include <stdexcept>

#include <fmt/format.h>
#include <tbb/parallel_for.h>
#include <CLI/CLI.hpp>

#include "harness/cell.h"
#include "harness/lookup_timing.h"
#include "harness/record.h"
#include "harness/table.h"
#include "schemes/interface/capabilities.h"
#include "schemes/interface/lightspace.h"

namespace fs = std::filesystem;

namespace sb {

namespace {

// VOAA at one node depth seen as a Decoder with the one filter size 1, so that answering and
// timing go through the same code as every exact lookup.
class VoaaLookup final : public Decoder {
 public:
  VoaaLookup(const Decoder& dag, const VoxelOccupancy& occupancy, uint32_t depth)
      : dag_(dag), occupancy_(occupancy), depth_(depth) {}

  void lookup(std::span<const Query> queries, int k, std::span<float> visibility) const override {
    if (k != 1) throw std::invalid_argument("a VOAA lookup has no filter size but 1");
    occupancy_.litFraction(queries, depth_, visibility);
  }
  SizeBreakdown size() const override { return dag_.size(); }
  void save(ByteWriter&) const override {
    throw std::logic_error("a VOAA lookup is a view of a structure, not one to save");
  }

 private:
  const Decoder& dag_;
  const VoxelOccupancy& occupancy_;
  uint32_t depth_;
};

// Hierarchical PCF (Scandolo et al. 2016a): the structure's own map `coarser` levels up.
class CoarseLevelLookup final : public Decoder {
 public:
  CoarseLevelLookup(const Decoder& full, const HierarchicalLookup& levels, int coarser)
      : full_(full), levels_(levels), coarser_(coarser) {}

  void lookup(std::span<const Query> queries, int k, std::span<float> visibility) const override {
    levels_.lookupCoarse(queries, coarser_, k, visibility);
  }
  SizeBreakdown size() const override { return full_.size(); }
  void save(ByteWriter&) const override {
    throw std::logic_error("a coarse-level lookup is a view of a structure, not one to save");
  }

 private:
  const Decoder& full_;
  const HierarchicalLookup& levels_;
  int coarser_;
};

// Every query's k×k answer, in parallel chunks.
std::vector<float> answersOf(const Decoder& decoder, int k, std::span<const Query> queries) {
  constexpr size_t kChunk = 4096;
  std::vector<float> answers(queries.size());
  tbb::parallel_for(size_t(0), (queries.size() + kChunk - 1) / kChunk, [&](size_t c) {
    const size_t begin = c * kChunk, n = std::min(kChunk, queries.size() - begin);
    decoder.lookup(queries.subspan(begin, n), k, std::span(answers).subspan(begin, n));
  });
  return answers;
}

}  // namespace

FilterError filterError(std::span<const float> approximate, std::span<const float> exact) {
  if (approximate.size() != exact.size())
    throw std::invalid_argument("filterError: the answer sets differ in size");
  FilterError error;
  if (exact.empty()) return error;
  double sum = 0, squares = 0;
  uint64_t over = 0;
  for (size_t q = 0; q < exact.size(); ++q) {
    const double difference = std::abs(double(approximate[q]) - double(exact[q]));
    sum += difference;
    squares += difference * difference;
    error.max = std::max(error.max, difference);
    over += difference > 0.1;
  }
  const double count = double(exact.size());
  error.meanAbs = sum / count;
  error.rms = std::sqrt(squares / count);
  error.overTenth = double(over) / count;
  return error;
}

std::vector<BuildOutcome> buildMraaLevels(const Scene& scene, const Light& light, DepthMode mode,
                                          const SchemeInfo& scheme, const ParamValues& params,
                                          uint32_t resolution, uint32_t levels) {
  if (levels > 4)
    throw std::invalid_argument(fmt::format(
        "MRAA has {} levels; at most 4, whose exact kernel 2^4 + 1 = 17 is the largest", levels));
  if (!validResolution(resolution >> levels))
    throw std::invalid_argument(fmt::format("MRAA level {} of {}² is below the smallest map, {}²",
                                            levels, resolution, kMinResolution));
  std::vector<BuildOutcome> built;
  for (uint32_t level = 1; level <= levels; ++level) {
    const DepthSource source(scene, light, mode, resolution >> level);
    built.push_back(
        buildStructure(source, scheme, params, BuildShape{defaultTileSize(source.resolution())}));
  }
  return built;
}

double DistantFiltersReport::mraaExtra() const {
  uint64_t coarse = 0;
  for (uint64_t bytes : mraaBytes) coarse += bytes;
  return double(coarse) / double(std::max<uint64_t>(fullBytes, 1));
}

nlohmann::json DistantFiltersReport::toJson() const {
  nlohmann::json filters = nlohmann::json::array();
  for (const DistantFilterRow& r : rows)
    filters.push_back({{"filter", r.filter},
                       {"answer", r.answer},
                       {"reference_k", r.referenceK},
                       {"mean_abs_error", r.error.meanAbs},
                       {"rms_error", r.error.rms},
                       {"max_error", r.error.max},
                       {"fraction_error_over_0_1", r.error.overTenth},
                       {"ns_per_query_1t", r.nsPerQuery},
                       {"exact_ns_per_query_1t", r.exactNsPerQuery},
                       {"bytes", r.bytes}});
  return {{"queries", queries},
          {"size_bytes",
           {{"full", fullBytes}, {"mraa_levels", mraaBytes}, {"mraa_extra_ratio", mraaExtra()}}},
          {"filters", filters}};
}

DistantFiltersReport evaluateDistantFilters(const BuildOutcome& full,
                                            std::span<const BuildOutcome> mraa, const QuerySet& set,
                                            const DistantFiltersOptions& options) {
  DistantFiltersReport report;
  report.queries = set.queries.size();
  report.fullBytes = totalBytes(full.decoder->size());
  for (uint32_t level = 1; level <= mraa.size(); ++level) {
    const MapInfo& map = mraa[level - 1].map;
    if (map.resolution != full.map.resolution >> level || map.mode != full.map.mode)
      throw std::invalid_argument(fmt::format("MRAA level {} must be the {} map at {}², not {}²",
                                              level, toString(full.map.mode),
                                              full.map.resolution >> level, map.resolution));
    report.mraaBytes.push_back(totalBytes(mraa[level - 1].decoder->size()));
  }

  // The exact full-resolution PCF of each reference kernel, answered (and timed) once.
  struct Exact {
    std::vector<float> answers;
    double nsPerQuery = 0;
  };
  std::map<int, Exact> exact;
  const auto addRow = [&](std::string filter, std::string answer, const Decoder& decoder, int k,
                          int referenceK, uint64_t bytes) {
    const auto [it, added] = exact.try_emplace(referenceK);
    Exact& reference = it->second;
    if (added) {
      reference.answers = answersOf(*full.decoder, referenceK, set.queries);
      if (options.time)
        reference.nsPerQuery = timeLookups(*full.decoder, set, referenceK).nsPerQuerySingleThread;
    }
    report.rows.push_back({std::move(filter), std::move(answer), referenceK,
                           filterError(answersOf(decoder, k, set.queries), reference.answers),
                           options.time ? timeLookups(decoder, set, k).nsPerQuerySingleThread : 0,
                           reference.nsPerQuery, bytes});
  };

  // VOAA: the node of side s against the (s + 1)² kernel, or 17², the largest exact one.
  if (const VoxelOccupancy* occupancy = full.decoder->voxelOccupancy())
    for (uint32_t side : options.voaaSides) {
      const uint32_t depth = occupancy->depthOfSide(side);
      addRow("VOAA", fmt::format("s = {} (depth {})", side, depth),
             VoaaLookup(*full.decoder, *occupancy, depth), 1, int(std::min(side + 1, 17u)),
             report.fullBytes);
    }
  // MRAA: level L's point and 3×3 lookups against the 2^L + 1 kernel at full resolution.
  for (uint32_t level = 0; level <= mraa.size(); ++level) {
    const BuildOutcome& built = level == 0 ? full : mraa[level - 1];
    for (int k : {1, 3})
      addRow(
          "MRAA",
          fmt::format("L = {} ({}), {}×{}", level, resolutionHeading(built.map.resolution), k, k),
          *built.decoder, k, mraaReferenceK(level),
          level == 0 ? report.fullBytes : report.mraaBytes[level - 1]);
  }
  // HPCF: the same footprints as MRAA, read from the full structure's own coarser levels.
  if (const HierarchicalLookup* levels = full.decoder->hierarchicalLookup())
    for (uint32_t level = 1; level <= mraa.size(); ++level)
      for (int k : {1, 3})
        addRow("HPCF",
               fmt::format("L = {} ({}), {}×{}", level,
                           resolutionHeading(full.map.resolution >> level), k, k),
               CoarseLevelLookup(*full.decoder, *levels, int(level)), k, mraaReferenceK(level),
               report.fullBytes);
  return report;
}

namespace {

struct CommandOptions {
  std::string scene = "city", mode = "closed", resolution = "4K", scheme = "cpvs-fast";
  std::string queries = "view", out = "results/distant-filters";
};

Table reportTable(const DistantFiltersReport& report) {
  Table table;
  table.title = "Distant filters against exact PCF (Sintorn 2014 §5, Scandolo 2016a)";
  table.unit_note =
      "absolute error in visibility (0–1) per query; ns/query single thread, median; MiB = 2²⁰ "
      "bytes of the structure the filter reads";
  table.header = {"filter", "answer",      "exact PCF", "mean |err|",     "RMS",
                  "max",    "err > 0.1 %", "ns/query",  "exact ns/query", "MiB"};
  for (const DistantFilterRow& r : report.rows) {
    const std::string k = fmt::format("{}×{}", r.referenceK, r.referenceK);
    table.rows.push_back({r.filter, r.answer, k, fmt::format("{:.4f}", r.error.meanAbs),
                          fmt::format("{:.4f}", r.error.rms), fmt::format("{:.4f}", r.error.max),
                          fmt::format("{:.2f}", 100 * r.error.overTenth),
                          fmt::format("{:.1f}", r.nsPerQuery),
                          fmt::format("{:.1f}", r.exactNsPerQuery),
                          fmt::format("{:.3f}", double(r.bytes) / (1 << 20))});
  }
  return table;
}

void runDistantFilters(const CommandOptions& o) {
  const Scene scene = openScene(o.scene);
  const SchemeInfo& scheme = findScheme(o.scheme);
  const DepthMode mode = depthModeFromString(o.mode);
  const uint32_t resolution = parseResolution(o.resolution);
  const Light light = sceneLight(scene, 0);
  const DepthSource source(scene, light, mode, resolution);
  constexpr uint32_t kMraaLevels = 4;  // R/2 … R/16: exact kernels 3×3 … 17×17

  fmt::print("building {} on {} ({}) at {} and its MRAA levels down to {}\n", scheme.name,
             scene.name, o.mode, resolutionHeading(resolution),
             resolutionHeading(resolution >> kMraaLevels));
  const ParamValues params = scheme.resolve({});
  const BuildOutcome full =
      buildStructure(source, scheme, params, BuildShape{defaultTileSize(resolution)});
  const std::vector<BuildOutcome> mraa =
      buildMraaLevels(scene, light, mode, scheme, params, resolution, kMraaLevels);
  // The query sets and sizes of the lookup benchmark (cell.cpp).
  const QuerySet set =
      o.queries == "view" ? standardViewQueries(scene, source) : standardUniformQueries();
  DistantFiltersOptions options;
  fmt::print("evaluating {} {} queries\n", set.queries.size(), set.name);
  const DistantFiltersReport report = evaluateDistantFilters(full, mraa, set, options);
  const bool hasVoaa = full.decoder->voxelOccupancy() != nullptr;

  std::string markdown = fmt::format(
      "# Distant filters: {} on `{}`, {}, {}\n\n"
      "Scene `{}`: {} triangles, hash {}; light 0. {} {} queries. Machine: {}.\n\n",
      scheme.name, o.scene, o.mode, resolutionHeading(resolution), scene.name,
      scene.triangleCount(), scene.hash(), set.queries.size(), set.name,
      machineInfo()["cpu"].get<std::string>());
  markdown += toMarkdown({reportTable(report)});
  markdown += fmt::format(
      "MRAA memory: levels R/2 … R/{} take {:.3f} MiB, {:.2f}× the full structure's {:.3f} MiB "
      "(all levels together {:.2f}×; Sintorn §5 says about twice the full structure).\n\n",
      1u << kMraaLevels, report.mraaExtra() * double(report.fullBytes) / (1 << 20),
      report.mraaExtra(), double(report.fullBytes) / (1 << 20), 1 + report.mraaExtra());
  if (hasVoaa)
    markdown +=
        "VOAA is a volume filter (Sintorn §5): the occupancy of the aligned s³ node holding the "
        "query's voxel, against an area kernel centred on the query texel at its depth. s = 32 "
        "is compared with 17×17, the largest exact kernel, which covers 17² of the node's 32² "
        "texels: its error also holds that difference in footprint.\n\n";
  if (scheme.kind == SchemeKind::Voxel)
    markdown +=
        "MRAA level L also quantises depth to R/2^L slices, so its answers are at the coarse "
        "voxel's centre.\n";
  else
    markdown +=
        "HPCF (hierarchical PCF, Scandolo et al. 2016a) reads level L of the structure's own "
        "hierarchy, a complete R/2^L map: the footprint of MRAA level L with no extra memory.\n";

  const fs::path base =
      fs::path(o.out) / fmt::format("{}_{}_{}_{}_{}", fileNamePart(scene.name), o.mode, scheme.name,
                                    fileNamePart(resolutionLabel(resolution)), set.name);
  nlohmann::json json = report.toJson();
  nlohmann::json paramsJson = nlohmann::json::object();
  for (const auto& [name, value] : full.params.text()) paramsJson[name] = value;
  json.update({{"format", "shadowbench-distant-filters/1"},
               {"scene",
                {{"name", scene.name},
                 {"spec", o.scene},
                 {"triangles", scene.triangleCount()},
                 {"hash", scene.hash()}}},
               {"light_index", 0},
               {"mode", o.mode},
               {"scheme", {{"name", scheme.name}, {"params", paramsJson}}},
               {"resolution", resolution},
               {"query_set", set.name},
               {"machine", machineInfo()},
               {"commit", sourceCommit(SHADOWBENCH_SOURCE_DIR)}});
  writeFileAtomically(fs::path(base) += ".md", markdown);
  writeJsonAtomically(fs::path(base) += ".json", json);
  fmt::print("\n{}\nwrote {}.md and .json\n", markdown, base.string());
}

}  // namespace

void addDistantFiltersCommand(CLI::App& app) {
  auto o = std::make_shared<CommandOptions>();
  CLI::App* sub = app.add_subcommand(
      "distant-filters",
      "Sintorn 2014 §5 VOAA and MRAA, and hierarchical PCF of the MH schemes: distant-shadow "
      "filters, error against exact PCF");
  sub->add_option("--scene,-s", o->scene, "generator, scene .json or model file")
      ->capture_default_str();
  sub->add_option("--mode,-m", o->mode, "dual depth mode: open, closed or static")
      ->capture_default_str();
  sub->add_option("--resolution,-r", o->resolution, "texels per side: 512, 4K, …")
      ->capture_default_str();
  sub->add_option("--scheme", o->scheme, "scheme name (VOAA rows for CPVS-format schemes)")
      ->capture_default_str();
  sub->add_option("--queries", o->queries, "query set: view (camera orbit samples) or uniform")
      ->capture_default_str()
      ->check(CLI::IsMember({"view", "uniform"}));
  sub->add_option("--out", o->out, "folder for <scene>_<mode>_<scheme>_<R>_<queries>.md/.json")
      ->capture_default_str();
  sub->callback([o] { runDistantFilters(*o); });
}

}  // namespace sb

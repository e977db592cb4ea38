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

}  // namespace sb

#include "harness/many_lights/statistics.h"

#include <algorithm>
#include <utility>

#include <fmt/format.h>

#include "harness/progress.h"

namespace sb {

Distribution distributionOf(std::vector<double> values) {
  Distribution d;
  if (values.empty()) return d;
  std::sort(values.begin(), values.end());
  const size_t n = values.size();
  d.min = values.front();
  d.max = values.back();
  d.median = n % 2 ? values[n / 2] : (values[n / 2 - 1] + values[n / 2]) / 2;
  for (double v : values) d.total += v;
  d.mean = d.total / double(n);
  return d;
}

Histogram histogramOf(std::span<const double> values, uint32_t bins) {
  Histogram h;
  if (values.empty() || bins == 0) return h;
  const auto [lo, hi] = std::minmax_element(values.begin(), values.end());
  h.lo = *lo;
  h.binWidth = (*hi - *lo) / bins;
  // Equal values (a scheme of fixed size) make one bin of width 0.
  h.counts.assign(h.binWidth > 0 ? bins : 1, 0);
  for (double v : values)
    ++h.counts[h.binWidth > 0 ? std::min<size_t>(size_t((v - h.lo) / h.binWidth), bins - 1) : 0];
  return h;
}

std::string histogramText(const Histogram& h, int digits) {
  constexpr uint32_t kBarWidth = 40;
  const uint32_t most = h.counts.empty() ? 0 : *std::max_element(h.counts.begin(), h.counts.end());
  std::string text;
  for (size_t b = 0; b < h.counts.size(); ++b) {
    const uint32_t bar = most ? (h.counts[b] * kBarWidth + most - 1) / most : 0;
    std::string bars;
    for (uint32_t i = 0; i < bar; ++i) bars += "█";
    text += fmt::format(
        "{:>10} – {:<10} {:<{}} {}\n", formatSignificant(h.lo + double(b) * h.binWidth, digits),
        formatSignificant(h.lo + double(b + 1) * h.binWidth, digits), bars, kBarWidth, h.counts[b]);
  }
  return text;
}

BuildSummary summariseBuilds(const std::vector<nlohmann::json>& records, uint32_t bins) {
  constexpr double kMiB = 1 << 20;
  std::vector<double> sizes, builds, depths;
  std::vector<std::pair<std::string, std::vector<double>>> phases;  // in order of appearance
  BuildSummary summary;
  summary.perLight = {
      "Many lights: per light",
      "bytes and milliseconds; build = depth map and encoding, wall clock",
      {"light", "x", "y", "z", "dx", "dy", "dz", "fov_degrees", "size_bytes", "build_ms",
       "depth_ms", "closed_fallbacks", "verified_queries", "mismatches"},
      {},
      "lights"};
  for (const nlohmann::json& r : records) {
    sizes.push_back(r["size_bytes"]["total"].get<double>() / kMiB);
    builds.push_back(r["time_s"]["total"].get<double>() * 1e3);
    depths.push_back(r["time_s"]["depth"].get<double>() * 1e3);
    for (const auto& [name, seconds] : r["time_s"]["phases"].items()) {
      auto phase = std::find_if(phases.begin(), phases.end(),
                                [&](const auto& p) { return p.first == name; });
      if (phase == phases.end()) phase = phases.insert(phase, {name, {}});
      phase->second.push_back(seconds.get<double>() * 1e3);
    }
    const nlohmann::json& light = r["light"];
    const bool verified = r.contains("verification");
    summary.perLight.rows.push_back(
        {fmt::format("{}", r["light_index"].get<uint32_t>()),
         formatSignificant(light["position"][0].get<double>()),
         formatSignificant(light["position"][1].get<double>()),
         formatSignificant(light["position"][2].get<double>()),
         formatSignificant(light["direction"][0].get<double>()),
         formatSignificant(light["direction"][1].get<double>()),
         formatSignificant(light["direction"][2].get<double>()),
         formatSignificant(light["fov_degrees"].get<double>()),
         fmt::format("{}", r["size_bytes"]["total"].get<uint64_t>()),
         formatSignificant(builds.back()), formatSignificant(depths.back()),
         fmt::format("{}", r["depth"]["closed_fallbacks"].get<uint64_t>()),
         verified ? fmt::format("{}", r["verification"]["queries"].get<uint64_t>()) : "–",
         verified ? fmt::format("{}", r["verification"]["mismatches"].get<uint64_t>()) : "–"});
  }

  // Kämpe §5.3 and Fig. 1: 165 lights at 8192³ on a GTX Titan with a Core i5-2500K; the
  // paper writes MB and gives no median.
  summary.distribution = {
      fmt::format("Many lights: {} structures (Kämpe 2015 Fig. 3)", records.size()),
      "MiB (2²⁰ bytes) and milliseconds, ours; the paper's rows as printed there (MB), 165 "
      "lights at 8192³; build = depth map and encoding, wall clock; depth map = tracing "
      "thread-seconds over threads, overlapping the encoder's phases",
      {"", "min", "median", "mean", "max", "total"},
      {},
      "distribution"};
  const auto row = [&](std::string label, const std::vector<double>& values) {
    const Distribution d = distributionOf(values);
    summary.distribution.rows.push_back({std::move(label), formatSignificant(d.min),
                                         formatSignificant(d.median), formatSignificant(d.mean),
                                         formatSignificant(d.max), formatSignificant(d.total)});
  };
  row("size (MiB)", sizes);
  summary.distribution.rows.push_back(
      {"size (MB), Kämpe 2015 (paper)", "0.3", "–", "0.5", "1.7", "96"});
  row("build (ms)", builds);
  summary.distribution.rows.push_back(
      {"build (ms), Kämpe 2015 (paper)", "–", "–", "114", "–", "19000"});
  row("depth map (ms)", depths);
  for (const auto& [name, values] : phases) row(fmt::format("phase {} (ms)", name), values);

  summary.histograms = {"Many lights: histograms",
                        "lights per bin [from, to) (the last bin includes its end)",
                        {"quantity", "from", "to", "lights"},
                        {},
                        "histogram"};
  const std::pair<const char*, const std::vector<double>*> quantities[] = {{"size (MiB)", &sizes},
                                                                           {"build (ms)", &builds}};
  for (const auto& [label, values] : quantities) {
    const Histogram h = histogramOf(*values, bins);
    for (size_t b = 0; b < h.counts.size(); ++b)
      summary.histograms.rows.push_back({label, formatSignificant(h.lo + double(b) * h.binWidth),
                                         formatSignificant(h.lo + double(b + 1) * h.binWidth),
                                         fmt::format("{}", h.counts[b])});
    summary.histogramText += fmt::format("{}:\n{}\n", label, histogramText(h));
  }
  return summary;
}

uint64_t summaryBytes(uint32_t bins) {
  constexpr uint64_t kQuantities = 2;  // size and build time
  constexpr uint64_t kBytesPerBin =
      sizeof(uint32_t) + 4 * sizeof(std::string) + sizeof(std::string);
  return kQuantities * bins * kBytesPerBin;
}

}  // namespace sb

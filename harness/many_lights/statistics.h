// Many local lights (Kämpe 2015 Fig. 3): the distribution of the lights' structure sizes and
// build times over their records, with the paper's figures beside ours.
#pragma once

#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "harness/table.h"

namespace sb {

struct Distribution {
  double min = 0, median = 0, mean = 0, max = 0, total = 0;
};
Distribution distributionOf(std::vector<double> values);

struct Histogram {
  double lo = 0, binWidth = 0;
  std::vector<uint32_t> counts;
};
Histogram histogramOf(std::span<const double> values, uint32_t bins);
// One line per bin: its range, a bar and its count.
std::string histogramText(const Histogram& histogram, int significantDigits = 3);

struct BuildSummary {
  Table distribution;  // min, median, mean, max, total of ours and the paper's
  Table perLight;      // one row per light
  Table histograms;    // one row per bin of size and of build time
  std::string histogramText;
};
BuildSummary summariseBuilds(const std::vector<nlohmann::json>& records, uint32_t bins = 12);

// What summariseBuilds holds at least for `bins` bins: per bin and quantity (size and build
// time) a count, a table row of four numbers and a line of text; checked before any build,
// since a histogram of 4·10⁹ bins would otherwise fail only after every light is built.
uint64_t summaryBytes(uint32_t bins);

}  // namespace sb

#include "harness/verify.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <limits>
#include <mutex>
#include <stdexcept>

#include <tbb/parallel_for.h>

#include <nlohmann/json.hpp>
#include "harness/query_sets.h"
#include "schemes/interface/splitmix.h"

namespace sb {

namespace {

// Windows are checked in their core; the halo holds the taps of a 17×17 PCF around it.
constexpr int64_t kCore = 64, kHalo = 8;
constexpr size_t kMaxExamples = 16;

// A position inside texel (i, j), jittered so that schemes are tested off the texel centre.
float insideTexel(int64_t i, float jitter, uint32_t resolution) {
  const float x = float((double(i) + jitter) / resolution);
  return texelOf(x, resolution) == i ? x : float((double(i) + 0.5) / resolution);
}

// The depths at which a texel's answer changes or must hold (DESIGN §4 / issue: lo, the next
// float below lo, hi, the next float above hi, a point inside the band, 0 and 1).
int probeDepths(DepthInterval in, float out[7]) {
  int n = 0;
  out[n++] = in.lo;
  out[n++] = std::nextafter(in.lo, -1.0f);
  out[n++] = 0.0f;
  out[n++] = 1.0f;
  out[n++] = in.lo + (std::min(in.hi, 1.0f) - in.lo) * 0.5f;
  if (std::isfinite(in.hi)) {
    out[n++] = in.hi;
    out[n++] = std::nextafter(in.hi, 2.0f);
  }
  return n;
}

// A texel on a shadow boundary: a 4-neighbour's first hit is far from its own.
bool onBoundary(const ReferenceWindow& window, int64_t i, int64_t j) {
  const float lo = window.at(i, j).lo;
  const int64_t di[] = {1, -1, 0, 0}, dj[] = {0, 0, 1, -1};
  for (int n = 0; n < 4; ++n)
    if (window.contains(i + di[n], j + dj[n]) &&
        std::abs(window.at(i + di[n], j + dj[n]).lo - lo) > 1.0f / 1024)
      return true;
  return false;
}

struct Checker {
  Checker(const Decoder& d, SchemeKind k, const MapInfo& m) : decoder(d), kind(k), map(m) {}

  const Decoder& decoder;
  SchemeKind kind;
  const MapInfo& map;
  std::atomic<uint64_t> queries{0}, mismatches{0};
  std::mutex examplesLock;
  std::vector<Mismatch> examples;

  // Queries and their reference ranges for one filter size, looked up in one batch.
  struct Batch {
    std::vector<Query> queries;
    std::vector<VisibilityRange> expected;
  };

  void run(Batch& batch, int k) {
    std::vector<float> got(batch.queries.size());
    decoder.lookup(batch.queries, k, got);
    uint64_t wrong = 0;
    for (size_t q = 0; q < got.size(); ++q) {
      if (batch.expected[q].contains(got[q])) continue;
      ++wrong;
      std::lock_guard lock(examplesLock);
      if (examples.size() < kMaxExamples)
        examples.push_back({batch.queries[q], k, got[q], batch.expected[q]});
    }
    queries += got.size();
    mismatches += wrong;
  }

  // Checks the texels of the window's core selected by `select(i, j)`; `pcf(hash, k)` picks
  // the texels that also get a k×k PCF lookup.
  template <class Select, class PcfSelect>
  void checkWindow(const ReferenceWindow& window, int64_t cx, int64_t cy, Select select,
                   PcfSelect pcf, uint64_t seed) {
    const auto tap = [&](int64_t i, int64_t j) {
      if (!window.contains(i, j)) throw std::logic_error("PCF tap outside the reference window");
      return window.at(i, j);
    };
    Batch batches[std::size(kStandardFilters)];
    const int64_t x1 = std::min<int64_t>(cx + kCore, map.resolution);
    const int64_t y1 = std::min<int64_t>(cy + kCore, map.resolution);
    for (int64_t j = cy; j < y1; ++j)
      for (int64_t i = cx; i < x1; ++i) {
        if (!select(i, j)) continue;
        const uint64_t h = mixBits(seed ^ mixBits(uint64_t(i) << 32 | uint64_t(j)));
        const Query at{insideTexel(i, unitFloat(h), map.resolution),
                       insideTexel(j, unitFloat(mixBits(h)), map.resolution), 0};
        float depths[7];
        const int n = probeDepths(window.at(i, j), depths);
        for (int d = 0; d < n; ++d) {
          batches[0].queries.push_back({at.x, at.y, depths[d]});
          batches[0].expected.push_back(acceptedRange(kind, map, i, j, 1, depths[d], tap));
        }
        for (size_t f = 1; f < std::size(kStandardFilters); ++f) {
          if (!pcf(h, kStandardFilters[f])) continue;
          // PCF at the texel's own surface, just behind it, and at a random depth.
          const float pcfDepths[] = {depths[0], depths[n - 1],
                                     unitFloat(mixBits(h ^ kStandardFilters[f]))};
          for (float z : pcfDepths) {
            batches[f].queries.push_back({at.x, at.y, z});
            batches[f].expected.push_back(
                acceptedRange(kind, map, i, j, kStandardFilters[f], z, tap));
          }
        }
      }
    for (size_t f = 0; f < std::size(kStandardFilters); ++f)
      if (!batches[f].queries.empty()) run(batches[f], kStandardFilters[f]);
  }
};

ReferenceWindow windowAround(const DepthSource& source, int64_t cx, int64_t cy) {
  return ReferenceWindow(source, cx - kHalo, cy - kHalo, kCore + 2 * kHalo, kCore + 2 * kHalo);
}

}  // namespace

nlohmann::json VerifyReport::toJson() const {
  nlohmann::json list = nlohmann::json::array();
  for (const Mismatch& m : examples)
    list.push_back({{"x", m.query.x},
                    {"y", m.query.y},
                    {"z", m.query.z},
                    {"k", m.k},
                    {"got", m.got},
                    {"expected", {m.expected.min, m.expected.max}}});
  return {{"method", method}, {"queries", queries}, {"mismatches", mismatches}, {"examples", list}};
}

VerifyReport verify(const Decoder& decoder, SchemeKind kind, const MapInfo& map,
                    const DepthSource& source, const VerifyOptions& options,
                    const std::function<void(uint64_t)>& progress) {
  Checker checker{decoder, kind, map};
  VerifyReport report;
  const int64_t windowsPerSide = (int64_t(map.resolution) + kCore - 1) / kCore;
  std::mutex progressLock;
  auto reportProgress = [&] {
    if (!progress) return;
    std::lock_guard lock(progressLock);
    progress(checker.queries.load());
  };

  if (map.resolution <= options.exhaustiveUpTo) {
    report.method = "exhaustive";
    tbb::parallel_for(int64_t(0), windowsPerSide * windowsPerSide, [&](int64_t w) {
      const int64_t cx = (w % windowsPerSide) * kCore, cy = (w / windowsPerSide) * kCore;
      const ReferenceWindow window = windowAround(source, cx, cy);
      checker.checkWindow(
          window, cx, cy, [](int64_t, int64_t) { return true; },
          [](uint64_t h, int k) { return (h >> 8) % (k <= 9 ? 8 : 64) == 0; }, options.seed);
      reportProgress();
    });
  } else {
    report.method = "sampled";
    // Random windows until enough queries: every boundary texel of a window with PCF, and a
    // uniform sixteenth of the others.
    std::atomic<uint64_t> round{0};
    while (checker.queries.load() < options.sampledQueries) {
      const uint64_t first = round.fetch_add(64);
      tbb::parallel_for(first, first + 64, [&](uint64_t n) {
        const uint64_t h = mixBits(options.seed ^ mixBits(n));
        const int64_t cx = int64_t(h % uint64_t(windowsPerSide)) * kCore;
        const int64_t cy = int64_t((h >> 32) % uint64_t(windowsPerSide)) * kCore;
        const ReferenceWindow window = windowAround(source, cx, cy);
        checker.checkWindow(
            window, cx, cy,
            [&](int64_t i, int64_t j) {
              return onBoundary(window, i, j) ||
                     mixBits(h ^ (uint64_t(i) << 32 | uint64_t(j))) % 16 == 0;
            },
            [](uint64_t hh, int k) { return (hh >> 8) % (k <= 9 ? 2 : 8) == 0; }, h);
        reportProgress();
      });
    }
  }
  report.queries = checker.queries;
  report.mismatches = checker.mismatches;
  report.examples = std::move(checker.examples);
  return report;
}

VerifyReport verifyKernels(const Decoder& decoder, const MapInfo& map,
                           std::span<const float> depths) {
  const int64_t r = map.resolution;
  const auto centre = [&](int64_t i) { return float((double(i) + 0.5) / double(r)); };
  Checker checker{decoder, SchemeKind::Depth, map};
  for (float z : depths) {
    // Lit taps of every rectangle from a summed-area table of the point answers.
    std::vector<Query> points(size_t(r * r));
    for (int64_t j = 0; j < r; ++j)
      for (int64_t i = 0; i < r; ++i) points[size_t(j * r + i)] = {centre(i), centre(j), z};
    std::vector<float> lit(points.size());
    decoder.lookup(points, 1, lit);
    std::vector<uint32_t> sums(size_t((r + 1) * (r + 1)), 0);
    for (int64_t j = 0; j < r; ++j)
      for (int64_t i = 0; i < r; ++i)
        sums[size_t((j + 1) * (r + 1) + i + 1)] =
            uint32_t(lit[size_t(j * r + i)] == 1.0f) + sums[size_t(j * (r + 1) + i + 1)] +
            sums[size_t((j + 1) * (r + 1) + i)] - sums[size_t(j * (r + 1) + i)];
    const auto litIn = [&](int64_t i0, int64_t j0, int64_t i1, int64_t j1) {  // [i0, i1) × [j0, j1)
      return sums[size_t(j1 * (r + 1) + i1)] - sums[size_t(j0 * (r + 1) + i1)] -
             sums[size_t(j1 * (r + 1) + i0)] + sums[size_t(j0 * (r + 1) + i0)];
    };
    for (size_t f = 1; f < std::size(kStandardFilters); ++f) {
      const int k = kStandardFilters[f];
      const int64_t radius = k / 2;
      Checker::Batch batch;
      batch.queries = points;
      batch.expected.reserve(points.size());
      for (int64_t j = 0; j < r; ++j)
        for (int64_t i = 0; i < r; ++i) {
          const int64_t i0 = std::max<int64_t>(i - radius, 0), i1 = std::min(i + radius + 1, r);
          const int64_t j0 = std::max<int64_t>(j - radius, 0), j1 = std::min(j + radius + 1, r);
          const int64_t off = int64_t(k) * k - (i1 - i0) * (j1 - j0);
          const float expected = float(off + litIn(i0, j0, i1, j1)) / float(k * k);
          batch.expected.push_back({expected, expected});
        }
      checker.run(batch, k);
    }
  }
  VerifyReport report;
  report.method = "kernels against taps";
  report.queries = checker.queries;
  report.mismatches = checker.mismatches;
  report.examples = std::move(checker.examples);
  return report;
}

std::vector<float> hitDepthQuantiles(const DepthSource& source, int count) {
  const ReferenceWindow map(source, 0, 0, source.resolution(), source.resolution());
  std::vector<float> hits;
  for (int64_t j = map.y0(); j < map.y1(); ++j)
    for (int64_t i = map.x0(); i < map.x1(); ++i)
      if (const float lo = map.at(i, j).lo; lo < 1.0f) hits.push_back(lo);
  std::sort(hits.begin(), hits.end());
  std::vector<float> depths;
  for (int n = 0; n < count && !hits.empty(); ++n)
    depths.push_back(hits[(hits.size() - 1) * size_t(2 * n + 1) / size_t(2 * count)]);
  return depths;
}

}  // namespace sb

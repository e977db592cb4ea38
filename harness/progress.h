// Progress of a long task (depth generation, a build, a verification) on stderr: quiet for short
// tasks, a live bar on a terminal, an occasional plain line in logs.
#pragma once

#include <atomic>
#include <chrono>
#include <cstdint>
#include <cstdio>
#include <mutex>
#include <optional>
#include <string>
#include <string_view>

namespace sb {

// How and when a Progress prints. The defaults are the command-line behaviour; tests change them.
struct ProgressStyle {
  std::FILE* out = stderr;
  std::optional<bool> terminal;  // default: whether `out` is a TTY
  bool quiet = false;            // the constructor also honours SHADOWBENCH_QUIET=1
  double silentSeconds = 2;      // nothing before this, so short tasks stay quiet
  double barSeconds = 0.5;       // least time between two bar updates on a terminal
  double lineSeconds = 10;       // least time between two plain lines elsewhere
};

class Progress {
 public:
  // `total` is the amount of work in `unit`s ("texels", "queries"); 0 when unknown, which shows
  // the count and rate without percent or ETA.
  Progress(std::string label, uint64_t total, std::string unit);
  Progress(std::string label, uint64_t total, std::string unit, ProgressStyle style);
  ~Progress();  // finish()es, so that an exception does not leave a bar line open
  Progress(const Progress&) = delete;
  Progress& operator=(const Progress&) = delete;

  void advance(uint64_t n);  // thread-safe
  void set(uint64_t done);   // thread-safe; never moves backwards (callbacks may race)
  // Ends the display: a final line with the count, time and rate when anything was printed.
  // Further calls and updates print nothing.
  void finish();

 private:
  void maybePrint();
  void print(double elapsed, bool final);
  std::string statusText(double elapsed) const;

  using Clock = std::chrono::steady_clock;
  const std::string label_, unit_;
  const uint64_t total_;
  const ProgressStyle style_;
  const bool terminal_;
  const Clock::time_point start_;
  std::atomic<uint64_t> done_{0};
  std::atomic<int64_t> nextPrintNs_;  // since start_; the first print waits silentSeconds
  std::mutex printing_;               // guards the members below and the output
  bool printed_ = false, finished_ = false;
  size_t lastWidth_ = 0;  // of the bar line, to blank what a shorter update leaves behind
};

// `value` in fixed notation with `digits` significant digits (more when its integer part is
// longer): 0.125, 3.82, 38.2, 382, 131072.
std::string formatSignificant(double value, int digits = 3);
// 38200000, "texels/s" → "38.2 Mtexels/s" (3 significant digits, SI prefixes up to E).
std::string formatSi(double value, std::string_view unit);
// 12.3 → "12.3s", 185 → "3m05s", 7400 → "2h03m".
std::string formatDuration(double seconds);

}  // namespace sb

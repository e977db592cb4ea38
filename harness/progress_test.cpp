// Progress reports of long runs: rates and durations as people read them, lines off a terminal,
// a bar on one, nothing when quiet, and counts from many threads.
#include <stdlib.h>

#include <cstdio>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include <catch2/catch.hpp>

#include "harness/progress.h"

namespace {

// SHADOWBENCH_QUIET set to `value` (nullptr: unset) for a scope; the caller's is restored after.
class QuietVariable {
 public:
  explicit QuietVariable(const char* value) {
    if (const char* old = std::getenv("SHADOWBENCH_QUIET")) saved_ = old;
    value ? setenv("SHADOWBENCH_QUIET", value, 1) : unsetenv("SHADOWBENCH_QUIET");
  }
  ~QuietVariable() {
    saved_ ? setenv("SHADOWBENCH_QUIET", saved_->c_str(), 1) : unsetenv("SHADOWBENCH_QUIET");
  }

 private:
  std::optional<std::string> saved_;
};

// What a Progress printed into a temporary file. The tests see the output whatever
// SHADOWBENCH_QUIET the test run was started with.
struct CapturedProgress {
  QuietVariable loud{nullptr};
  std::FILE* file = std::tmpfile();
  ~CapturedProgress() { std::fclose(file); }
  sb::ProgressStyle style(bool terminal) const {
    sb::ProgressStyle s;
    s.out = file;
    s.terminal = terminal;
    s.silentSeconds = 0;
    s.barSeconds = 0;
    s.lineSeconds = 0;
    return s;
  }
  std::string text() const {
    std::fflush(file);
    std::rewind(file);
    std::string out;
    char buffer[512];
    for (size_t n; (n = std::fread(buffer, 1, sizeof buffer, file)) > 0;) out.append(buffer, n);
    return out;
  }
};

}  // namespace

TEST_CASE("Progress formats rates with SI prefixes and durations", "[progress]") {
  CHECK(sb::formatSi(38.2e6, "texels/s") == "38.2 Mtexels/s");
  CHECK(sb::formatSi(999.7e3, "texels") == "1.00 Mtexels");
  CHECK(sb::formatSi(512, "queries") == "512 queries");
  CHECK(sb::formatSi(0, "texels/s") == "0 texels/s");
  CHECK(sb::formatSi(68.7e9, "texels") == "68.7 Gtexels");
  CHECK(sb::formatDuration(12.34) == "12.3s");
  CHECK(sb::formatDuration(185) == "3m05s");
  CHECK(sb::formatDuration(7400) == "2h03m");
  CHECK(sb::formatSignificant(0.125) == "0.125");
  CHECK(sb::formatSignificant(99.96) == "100");
  CHECK(sb::formatSignificant(131072) == "131072");
  CHECK(sb::formatSignificant(3.2) == "3.20");
}

TEST_CASE("Progress prints lines off a terminal and a final line with the total time",
          "[progress]") {
  CapturedProgress captured;
  {
    sb::Progress progress("build", 1000, "texels", captured.style(false));
    progress.advance(250);
    progress.set(500);
    progress.set(100);  // never backwards
    progress.finish();
    progress.advance(500);  // after finish: silent
  }
  const std::string out = captured.text();
  CHECK(out.find("build:  25.0% of 1.00 ktexels") != std::string::npos);
  CHECK(out.find("build:  50.0%") != std::string::npos);
  CHECK(out.find("stopped at 50.0%, 500 texels in ") != std::string::npos);
  CHECK(out.find('\r') == std::string::npos);
  CHECK(std::count(out.begin(), out.end(), '\n') == 4);
}

TEST_CASE("Progress draws a bar on a terminal and ends it with a newline", "[progress]") {
  CapturedProgress captured;
  {
    sb::Progress progress("depth", 4, "texels", captured.style(true));
    for (int i = 0; i < 4; ++i) progress.advance(1);
  }  // the destructor finishes
  const std::string out = captured.text();
  CHECK(out.find("\rdepth [##############################] 100.0%") != std::string::npos);
  CHECK(out.find("depth: 4.00 texels in ") != std::string::npos);
  CHECK(out.back() == '\n');
  CHECK(std::count(out.begin(), out.end(), '\n') == 1);
}

TEST_CASE("Progress with total 0 shows count and rate; quiet ones print nothing", "[progress]") {
  CapturedProgress unknownTotal;
  {
    sb::Progress progress("verify", 0, "queries", unknownTotal.style(false));
    progress.advance(1'000'000);
    progress.finish();
  }
  CHECK(unknownTotal.text().find("verify: 1.00 Mqueries, ") != std::string::npos);
  CHECK(unknownTotal.text().find("nan") == std::string::npos);
  CHECK(unknownTotal.text().find("inf") == std::string::npos);

  CapturedProgress quiet;
  {
    sb::ProgressStyle style = quiet.style(true);
    style.quiet = true;
    sb::Progress progress("q", 10, "texels", style);
    progress.advance(5);
  }
  CHECK(quiet.text().empty());

  CapturedProgress byEnvironment;
  {
    QuietVariable quietRun("1");
    sb::Progress progress("q", 10, "texels", byEnvironment.style(false));
    progress.advance(5);
  }
  CHECK(byEnvironment.text().empty());

  // Short tasks stay quiet: nothing in the first seconds, so nothing at the end either.
  CapturedProgress shortTask;
  {
    sb::ProgressStyle style = shortTask.style(false);
    style.silentSeconds = 2;
    sb::Progress progress("short", 10, "texels", style);
    progress.advance(10);
  }
  CHECK(shortTask.text().empty());
}

TEST_CASE("Progress advances correctly from many threads", "[progress]") {
  CapturedProgress captured;
  {
    sb::Progress progress("parallel", 8 * 10000, "texels", captured.style(false));
    std::vector<std::thread> workers;
    for (int t = 0; t < 8; ++t)
      workers.emplace_back([&] {
        for (int i = 0; i < 10000; ++i) progress.advance(1);
      });
    for (auto& w : workers) w.join();
    progress.finish();
  }
  CHECK(captured.text().find("parallel: 80.0 ktexels in ") != std::string::npos);
}

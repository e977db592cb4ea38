#include "harness/progress.h"

#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <limits>

#include <fmt/format.h>

namespace sb {

namespace {

constexpr int64_t kNever = std::numeric_limits<int64_t>::max();
constexpr int kBarWidth = 30;

int64_t nanoseconds(double seconds) {
  return int64_t(seconds * 1e9);
}

bool quietByEnvironment() {
  const char* quiet = std::getenv("SHADOWBENCH_QUIET");
  return quiet && *quiet && std::string_view(quiet) != "0";
}

std::string bar(double fraction) {
  const int filled = int(std::lround(std::clamp(fraction, 0.0, 1.0) * kBarWidth));
  std::string drawn(size_t(kBarWidth + 2), '-');
  drawn.front() = '[', drawn.back() = ']';
  std::fill_n(drawn.begin() + 1, filled, '#');
  return drawn;
}

}  // namespace

std::string formatSignificant(double value, int digits) {
  if (!std::isfinite(value)) return "?";
  if (value == 0) return "0";
  const auto decimalsFor = [&](double v) {
    return std::clamp(digits - 1 - int(std::floor(std::log10(std::fabs(v)))), 0, 15);
  };
  int decimals = decimalsFor(value);
  // Rounding may carry into a new leading digit (99.96 → 100.0): then one decimal fewer.
  const double scale = std::pow(10.0, decimals);
  const double rounded = std::round(value * scale) / scale;
  if (rounded != 0) decimals = std::min(decimals, decimalsFor(rounded));
  return fmt::format("{:.{}f}", value, decimals);
}

std::string formatSi(double value, std::string_view unit) {
  static constexpr const char* kPrefixes[] = {"", "k", "M", "G", "T", "P", "E"};
  if (!std::isfinite(value)) return fmt::format("? {}", unit);
  const char* sign = value < 0 ? "-" : "";
  value = std::fabs(value);
  size_t prefix = 0;
  while (value >= 999.5 && prefix + 1 < std::size(kPrefixes)) value /= 1000, ++prefix;
  return fmt::format("{}{} {}{}", sign, formatSignificant(value), kPrefixes[prefix], unit);
}

std::string formatDuration(double seconds) {
  if (!std::isfinite(seconds) || seconds < 0) return "?";
  if (seconds < 59.95) return fmt::format("{:.1f}s", seconds);
  if (seconds < 3599.5) {
    const long long whole = std::llround(seconds);
    return fmt::format("{}m{:02}s", whole / 60, whole % 60);
  }
  const long long minutes = std::llround(seconds / 60);
  return fmt::format("{}h{:02}m", minutes / 60, minutes % 60);
}

Progress::Progress(std::string label, uint64_t total, std::string unit)
    : Progress(std::move(label), total, std::move(unit), ProgressStyle{}) {}

Progress::Progress(std::string label, uint64_t total, std::string unit, ProgressStyle style)
    : label_(std::move(label)),
      unit_(std::move(unit)),
      total_(total),
      style_(style),
      terminal_(style.terminal.value_or(style.out && isatty(fileno(style.out)))),
      start_(Clock::now()),
      nextPrintNs_(style.quiet || !style.out || quietByEnvironment()
                       ? kNever
                       : nanoseconds(style.silentSeconds)) {}

Progress::~Progress() {
  try {
    finish();
  } catch (...) {
    // Out of memory while formatting the last line: the display is not worth terminate().
  }
}

void Progress::advance(uint64_t n) {
  done_.fetch_add(n, std::memory_order_relaxed);
  maybePrint();
}

void Progress::set(uint64_t done) {
  uint64_t seen = done_.load(std::memory_order_relaxed);
  while (seen < done && !done_.compare_exchange_weak(seen, done, std::memory_order_relaxed)) {
  }
  maybePrint();
}

void Progress::maybePrint() {
  // The common case, from any thread: one clock read and one relaxed load, no lock.
  const int64_t now =
      std::chrono::duration_cast<std::chrono::nanoseconds>(Clock::now() - start_).count();
  if (now < nextPrintNs_.load(std::memory_order_relaxed)) return;
  // Whoever holds the lock is printing; the others need not wait for it.
  std::unique_lock lock(printing_, std::try_to_lock);
  if (!lock.owns_lock() || finished_ || now < nextPrintNs_.load(std::memory_order_relaxed)) return;
  nextPrintNs_.store(now + nanoseconds(terminal_ ? style_.barSeconds : style_.lineSeconds),
                     std::memory_order_relaxed);
  print(double(now) * 1e-9, false);
}

void Progress::finish() {
  std::lock_guard lock(printing_);
  if (finished_) return;
  finished_ = true;
  nextPrintNs_.store(kNever, std::memory_order_relaxed);
  if (printed_) print(std::chrono::duration<double>(Clock::now() - start_).count(), true);
}

std::string Progress::statusText(double elapsed) const {
  const uint64_t done = done_.load(std::memory_order_relaxed);
  const double rate = elapsed > 0 ? double(done) / elapsed : 0;
  const std::string rateText = formatSi(rate, unit_ + "/s");
  if (total_ == 0) return fmt::format("{}, {}", formatSi(double(done), unit_), rateText);
  const double fraction = std::min(1.0, double(done) / double(total_));
  const std::string eta = done >= total_ ? "0s"
                          : rate > 0     ? formatDuration(double(total_ - done) / rate)
                                         : std::string("?");
  return fmt::format("{:5.1f}% of {}, {}, ETA {}", fraction * 100, formatSi(double(total_), unit_),
                     rateText, eta);
}

void Progress::print(double elapsed, bool final) {
  const uint64_t done = done_.load(std::memory_order_relaxed);
  std::string line;
  if (!final) {
    line = terminal_
               ? fmt::format("{} {} {}", label_, bar(total_ ? double(done) / double(total_) : 0),
                             statusText(elapsed))
               : fmt::format("{}: {}", label_, statusText(elapsed));
  } else {
    const std::string rate = formatSi(elapsed > 0 ? double(done) / elapsed : 0, unit_ + "/s");
    // A task ended early (an exception unwinding) says so rather than looking finished.
    const std::string outcome =
        total_ && done < total_
            ? fmt::format("stopped at {:.1f}%, ", 100.0 * double(done) / double(total_))
            : "";
    line = fmt::format("{}: {}{} in {} ({})", label_, outcome, formatSi(double(done), unit_),
                       formatDuration(elapsed), rate);
  }
  // '\r' returns to the bar's start; spaces blank what a longer previous line left there.
  const size_t blank = lastWidth_ > line.size() ? lastWidth_ - line.size() : 0;
  const std::string text =
      terminal_ ? fmt::format("\r{}{}{}", line, std::string(blank, ' '), final ? "\n" : "")
                : line + "\n";
  // A display that cannot be written (stderr closed) must not end the build it reports on.
  std::fwrite(text.data(), 1, text.size(), style_.out);
  std::fflush(style_.out);
  lastWidth_ = line.size();
  printed_ = true;
}

}  // namespace sb

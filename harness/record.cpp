#include "harness/record.h"

#include <malloc.h>
#include <sys/utsname.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <system_error>
#include <thread>

#include <fmt/format.h>

namespace fs = std::filesystem;

namespace sb {

namespace {

// The value of the first "key: value" line of a /proc file whose key is `key`, trimmed;
// empty when there is none.
std::string procField(const char* file, std::string_view key) {
  std::ifstream in(file);
  for (std::string line; std::getline(in, line);) {
    const size_t colon = line.find(':');
    if (colon == std::string::npos) continue;
    std::string_view name(line.data(), colon);
    while (!name.empty() && (name.back() == ' ' || name.back() == '\t')) name.remove_suffix(1);
    if (name != key) continue;
    const size_t begin = line.find_first_not_of(" \t", colon + 1);
    if (begin == std::string::npos) return {};
    const size_t end = line.find_last_not_of(" \t\r");
    return line.substr(begin, end - begin + 1);
  }
  return {};
}

// A "/proc" size such as "16314236 kB" in bytes; 0 when absent or malformed.
uint64_t procKilobytes(const char* file, std::string_view key) {
  const std::string value = procField(file, key);
  uint64_t kilobytes = 0;
  bool any = false;
  for (char c : value) {
    if (c < '0' || c > '9') break;
    kilobytes = kilobytes * 10 + uint64_t(c - '0');
    any = true;
  }
  return any ? kilobytes * 1024 : 0;
}

std::string cpuModel() {
  // x86 names the model; other architectures use other keys, or none.
  for (const char* key : {"model name", "Hardware", "cpu model", "Processor", "cpu"}) {
    std::string model = procField("/proc/cpuinfo", key);
    if (!model.empty()) return model;
  }
  return "unknown";
}

std::string operatingSystem() {
  utsname name{};
  if (uname(&name) != 0) return "unknown";
  return fmt::format("{} {} {}", name.sysname, name.release, name.machine);
}

// `text` quoted for /bin/sh: inside single quotes nothing is special but the quote itself.
std::string shellQuoted(const std::string& text) {
  std::string quoted = "'";
  for (char c : text) quoted += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return quoted + "'";
}

// The standard output of a shell command, or nullopt when it cannot run or exits non-zero.
std::optional<std::string> commandOutput(const std::string& command) {
  FILE* pipe = popen(command.c_str(), "r");
  if (!pipe) return std::nullopt;
  std::string output;
  char buffer[256];
  for (size_t n; (n = fread(buffer, 1, sizeof buffer, pipe)) > 0;) output.append(buffer, n);
  const int status = pclose(pipe);
  if (status == -1 || !WIFEXITED(status) || WEXITSTATUS(status) != 0) return std::nullopt;
  return output;
}

std::string trimmed(std::string text) {
  const size_t end = text.find_last_not_of(" \t\r\n");
  text.erase(end == std::string::npos ? 0 : end + 1);
  return text;
}

uint64_t fnv1a(std::string_view text) {
  uint64_t hash = 0xcbf29ce484222325ull;
  for (unsigned char c : text) hash = (hash ^ c) * 0x100000001b3ull;
  return hash;
}

template <typename T>
bool has(const nlohmann::json& object, const char* key, T check) {
  const auto it = object.find(key);
  return it != object.end() && check(*it);
}

bool isString(const nlohmann::json& j) {
  return j.is_string();
}
bool isNumber(const nlohmann::json& j) {
  return j.is_number();
}

std::string paramValueText(const nlohmann::json& value) {
  return value.is_string() ? value.get<std::string>() : value.dump();
}

}  // namespace

nlohmann::json machineInfo() {
  return {{"cpu", cpuModel()},
          {"cores", std::thread::hardware_concurrency()},
          {"memory_bytes", procKilobytes("/proc/meminfo", "MemTotal")},
          {"os", operatingSystem()}};
}

std::string sourceCommit(const fs::path& sourceDir) {
  try {
    const std::string git = "git -C " + shellQuoted(sourceDir.string());
    const auto head = commandOutput(git + " rev-parse --short=12 HEAD 2>/dev/null");
    if (!head || trimmed(*head).empty()) return "unknown";
    const auto changes =
        commandOutput(git + " status --porcelain --untracked-files=no 2>/dev/null");
    // A status that cannot be read is reported as dirty: claiming a clean tree must be earned.
    const bool dirty = !changes || !trimmed(*changes).empty();
    return trimmed(*head) + (dirty ? "-dirty" : "");
  } catch (...) {
    return "unknown";
  }
}

uint64_t availableMemoryBytes() {
  return procKilobytes("/proc/meminfo", "MemAvailable");
}
uint64_t currentRssBytes() {
  return procKilobytes("/proc/self/status", "VmRSS");
}
uint64_t peakRssBytes() {
  return procKilobytes("/proc/self/status", "VmHWM");
}

void resetPeakRss() {
  // Heap pages an earlier build freed stay resident until trimmed, and would count in this
  // build's baseline and peak (a sweep builds cell after cell in one process).
  malloc_trim(0);
  // "5" resets VmHWM to the current RSS (Linux ≥ 4.0). Without it the peak includes whatever
  // ran before, which only overstates; nothing to report.
  if (FILE* file = std::fopen("/proc/self/clear_refs", "w")) {
    std::fputs("5", file);
    std::fclose(file);
  }
}

void writeJsonAtomically(const fs::path& path, const nlohmann::json& record) {
  // Invalid UTF-8 (a scene named from raw bytes) is replaced rather than losing the record.
  writeFileAtomically(path,
                      record.dump(2, ' ', false, nlohmann::json::error_handler_t::replace) + "\n");
}

bool isCompleteRecord(const nlohmann::json& r) {
  if (!r.is_object()) return false;
  const auto format = r.find("format");
  const auto complete = r.find("complete");
  if (format == r.end() || !format->is_string() || format->get<std::string>() != kRecordFormat)
    return false;
  if (complete == r.end() || !complete->is_boolean() || !complete->get<bool>()) return false;
  const auto scene = r.find("scene");
  const auto scheme = r.find("scheme");
  const auto size = r.find("size_bytes");
  return scene != r.end() && scene->is_object() && has(*scene, "name", isString) &&
         scheme != r.end() && scheme->is_object() && has(*scheme, "name", isString) &&
         has(r, "mode", isString) &&
         has(r, "resolution",
             [](auto& j) { return j.is_number_integer() && j.template get<int64_t>() > 0; }) &&
         size != r.end() && size->is_object() && has(*size, "total", isNumber);
}

std::optional<nlohmann::json> readRecord(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return std::nullopt;
  std::ostringstream text;
  text << in.rdbuf();
  if (in.bad()) return std::nullopt;
  nlohmann::json record = nlohmann::json::parse(text.str(), nullptr, /*allow_exceptions=*/false);
  if (record.is_discarded() || !isCompleteRecord(record)) return std::nullopt;
  return record;
}

LoadedRecords readRecords(const fs::path& dir) {
  std::vector<fs::path> candidates;
  std::error_code error;
  for (fs::recursive_directory_iterator
           it(dir, fs::directory_options::skip_permission_denied, error),
       end;
       !error && it != end; it.increment(error)) {
    std::error_code typeError;
    if (it->is_regular_file(typeError) && it->path().extension() == ".json")
      candidates.push_back(it->path());
  }
  std::sort(candidates.begin(), candidates.end());

  LoadedRecords loaded;
  for (const fs::path& path : candidates) {
    if (auto record = readRecord(path)) {
      loaded.records.push_back(std::move(*record));
      loaded.paths.push_back(path);
    } else {
      loaded.skipped.push_back(path);
    }
  }
  return loaded;
}

std::string fileNamePart(std::string_view text) {
  std::string part;
  bool unusual = false;  // lost more than case and ordinary punctuation: add a hash
  for (char c : text) {
    if (c >= 'A' && c <= 'Z') c = char(c - 'A' + 'a');
    if ((c >= 'a' && c <= 'z') || (c >= '0' && c <= '9') || c == '.') {
      part += c;
      continue;
    }
    unusual = unusual || std::string_view("-_:,= ").find(c) == std::string_view::npos;
    if (part.empty() || part.back() != '-') part += '-';
  }
  // A leading '.' would hide the file; edge dashes only make names harder to read.
  const size_t begin = part.find_first_not_of(".-");
  unusual = unusual || (begin != std::string::npos && part.find('.') < begin);
  part = begin == std::string::npos ? std::string() : part.substr(begin);
  while (!part.empty() && part.back() == '-') part.pop_back();
  if (part.empty()) {
    part = "x";
    unusual = unusual || !text.empty();
  }
  if (unusual) part += fmt::format("-{:08x}", uint32_t(fnv1a(text)));
  return part;
}

std::string cellKey(const nlohmann::json& record) {
  const nlohmann::json& scheme = record.at("scheme");
  std::string key = fileNamePart(record.at("scene").at("name").get<std::string>());
  key += fmt::format("_{}_{}_{}", record.value("light_index", 0u),
                     fileNamePart(record.at("mode").get<std::string>()),
                     fileNamePart(scheme.at("name").get<std::string>()));
  if (const auto params = scheme.find("params"); params != scheme.end() && params->is_object())
    for (const auto& [name, value] : params->items())  // sorted by name: a stable order
      key += fmt::format("_{}-{}", fileNamePart(name), fileNamePart(paramValueText(value)));
  key += fmt::format("_{}", record.at("resolution").get<uint64_t>());

  // File names stop at 255 bytes; the temporary adds a prefix and suffix to this.
  constexpr size_t kMaxKey = 200;
  if (key.size() > kMaxKey)
    key = fmt::format("{}-{:016x}", key.substr(0, kMaxKey - 17), fnv1a(key));
  return key;
}

}  // namespace sb

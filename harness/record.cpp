#include "harness/record.h"

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <fstream>
#include <sstream>
#include <system_error>

#include <fmt/format.h>

namespace fs = std::filesystem;

namespace sb {

void writeJsonAtomically(const fs::path& path, const nlohmann::json& json) {
  // Invalid UTF-8 (a scene named from raw bytes) is replaced rather than losing the record.
  writeFileAtomically(path,
                      json.dump(2, ' ', false, nlohmann::json::error_handler_t::replace) + "\n");
}

void writeRecord(const fs::path& path, const Record& record) {
  writeJsonAtomically(path, nlohmann::json(record));
}

Record loadRecord(const fs::path& path) {
  std::error_code error;
  if (fs::is_directory(path, error))
    throw RecordError(fmt::format("'{}' is a folder, not a record", path.string()));
  std::ifstream in(path, std::ios::binary);
  if (!in)
    throw RecordError(fmt::format("'{}' cannot be read: {}", path.string(), std::strerror(errno)));
  std::ostringstream text;
  text << in.rdbuf();
  if (in.bad()) throw RecordError(fmt::format("'{}' cannot be read", path.string()));
  if (text.str().find_first_not_of(" \t\r\n") == std::string::npos)
    throw RecordError(fmt::format("'{}' is empty", path.string()));
  const nlohmann::json json =
      nlohmann::json::parse(text.str(), nullptr, /*allow_exceptions=*/false);
  if (json.is_discarded())
    throw RecordError(fmt::format("'{}' is not JSON (cut short while written?)", path.string()));
  try {
    return json.get<Record>();
  } catch (const RecordError& error) {
    throw RecordError(fmt::format("'{}': {}", path.string(), error.what()));
  }
}

std::optional<nlohmann::json> readRecord(const fs::path& path) {
  try {
    return nlohmann::json(loadRecord(path));
  } catch (const RecordError&) {
    return std::nullopt;
  }
}

LoadedRecords readRecords(const fs::path& dir) {
  std::vector<fs::path> candidates;
  std::error_code error;
  for (fs::recursive_directory_iterator
           it(dir, fs::directory_options::skip_permission_denied, error),
       end;
       !error && it != end; it.increment(error)) {
    std::error_code typeError;
    if (it->is_directory(typeError) && it->path().filename() == kSupersededFolder)
      it.disable_recursion_pending();
    else if (it->is_regular_file(typeError) && it->path().extension() == ".json")
      candidates.push_back(it->path());
  }
  std::sort(candidates.begin(), candidates.end());

  LoadedRecords loaded;
  for (const fs::path& path : candidates) {
    try {
      loaded.records.push_back(loadRecord(path));
      loaded.paths.push_back(path);
    } catch (const RecordError& error) {
      loaded.skipped.push_back({path, error.what()});
    }
  }
  return loaded;
}

}  // namespace sb

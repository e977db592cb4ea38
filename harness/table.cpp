#include "harness/table.h"

#include <algorithm>
#include <map>
#include <set>
#include <tuple>

#include <fmt/format.h>

#include "harness/cell_key.h"
#include "harness/record.h"
#include "harness/table_number.h"

namespace fs = std::filesystem;

namespace sb {

namespace {

const std::string kMissing = "–";
constexpr double kMiB = 1 << 20;
constexpr std::string_view kBaseline = "sm32";

// --- ordering -------------------------------------------------------------------------------

// "search=200" before "search=1000": digit runs compare as numbers.
bool naturalLess(std::string_view a, std::string_view b) {
  const auto isDigit = [](char c) { return c >= '0' && c <= '9'; };
  size_t i = 0, j = 0;
  while (i < a.size() && j < b.size()) {
    if (isDigit(a[i]) && isDigit(b[j])) {
      const size_t i0 = i, j0 = j;
      while (i < a.size() && isDigit(a[i])) ++i;
      while (j < b.size() && isDigit(b[j])) ++j;
      std::string_view x = a.substr(i0, i - i0), y = b.substr(j0, j - j0);
      x.remove_prefix(std::min(x.find_first_not_of('0'), x.size()));
      y.remove_prefix(std::min(y.find_first_not_of('0'), y.size()));
      if (x.size() != y.size()) return x.size() < y.size();
      if (x != y) return x < y;
    } else {
      if (a[i] != b[j]) return a[i] < b[j];
      ++i, ++j;
    }
  }
  return a.size() - i < b.size() - j;
}

// The baseline first, then by name.
bool schemeNameLess(const std::string& a, const std::string& b) {
  return std::make_tuple(a != kBaseline, a) < std::make_tuple(b != kBaseline, b);
}

// A scheme with its parameters: one row of the size and time tables.
struct Variant {
  std::string scheme;
  std::string params;  // "search=1000, height=3"; empty without parameters

  std::string label() const {
    return params.empty() ? scheme : fmt::format("{} ({})", scheme, params);
  }
  bool operator==(const Variant&) const = default;
  bool operator<(const Variant& o) const {
    if (scheme != o.scheme) return schemeNameLess(scheme, o.scheme);
    return naturalLess(params, o.params);
  }
};

Variant variantOf(const Record& record) {
  Variant variant{record.scheme.name, {}};
  for (const auto& [name, value] : record.scheme.params)
    variant.params += fmt::format("{}{}={}", variant.params.empty() ? "" : ", ", name, value);
  return variant;
}

// --- choosing one record per table cell ---------------------------------------------------------

// What one number of the tables stands for: a table (scene, light, mode) and a cell in it.
using TableCell = std::tuple<std::string, uint64_t, std::string, Variant, uint64_t>;

TableCell tableCellOf(const Record& r) {
  return {r.scene.name, r.lightIndex, r.mode, variantOf(r), r.resolution};
}

// The records the tables show: of several records of one table cell the newest ("created"); of
// equal times the later one. `duplicate(used, unused, why)` hears of each record left out.
template <typename Duplicate>
std::vector<const Record*> recordsShown(const std::vector<Record>& records, Duplicate duplicate) {
  std::map<TableCell, std::vector<size_t>> byCell;
  for (size_t i = 0; i < records.size(); ++i) byCell[tableCellOf(records[i])].push_back(i);
  std::vector<const Record*> shown;
  for (const auto& [cell, indices] : byCell) {
    size_t used = indices.front();
    for (size_t i : indices)
      if (records[used].created <= records[i].created) used = i;
    shown.push_back(&records[used]);
    for (size_t i : indices)
      if (i != used)
        duplicate(used, i,
                  records[i].created == records[used].created
                      ? fmt::format("both created {}; the later file is used",
                                    records[used].created.empty() ? "at an unknown time"
                                                                  : records[used].created)
                      : fmt::format(
                            "created {}, the used one {}",
                            records[i].created.empty() ? "at an unknown time" : records[i].created,
                            records[used].created));
  }
  return shown;
}

// --- grouping -------------------------------------------------------------------------------

using Cell = std::pair<Variant, uint64_t>;  // (scheme with parameters, resolution)

// The records of one (scene, light index, mode): one table of each kind.
struct Group {
  std::string scene;
  uint64_t light = 0;
  std::string mode;
  std::map<Cell, const Record*> records;
  std::set<Variant> variants;
  std::set<uint64_t> resolutions;

  std::string describe() const { return fmt::format("{}, light {}, {}", scene, light, mode); }
  std::string slug(std::string_view kind) const {
    return fmt::format("{}_{}_{}_{}", kind, fileNamePart(scene), light, fileNamePart(mode));
  }
  const Record* at(const Variant& v, uint64_t r) const {
    const auto it = records.find({v, r});
    return it == records.end() ? nullptr : it->second;
  }
};

std::vector<Group> groupRecords(const std::vector<const Record*>& records) {
  std::map<std::tuple<std::string, uint64_t, std::string>, Group> groups;
  for (const Record* record : records) {
    Group& group = groups[{record->scene.name, record->lightIndex, record->mode}];
    group.scene = record->scene.name, group.light = record->lightIndex, group.mode = record->mode;
    const Variant variant = variantOf(*record);
    group.variants.insert(variant);
    group.resolutions.insert(record->resolution);
    group.records[{variant, record->resolution}] = record;
  }
  std::vector<Group> ordered;
  for (auto& [key, group] : groups) ordered.push_back(std::move(group));
  return ordered;
}

// --- cells ----------------------------------------------------------------------------------

std::string significant(double value) {
  return formatTableNumber(value, NumberKind::Significant);
}

std::string mib(double bytes) {
  return significant(bytes / kMiB);
}

double shadowMap16Bytes(uint64_t resolution) {
  return double(resolution) * double(resolution) * 2;
}

std::string percentOf16Bit(double bytes, uint64_t resolution) {
  return significant(100 * bytes / shadowMap16Bytes(resolution));
}

std::string buildTimeCell(const Record& record) {
  if (!record.time) return kMissing;
  return record.depth ? fmt::format("{} ({})", significant(record.time->total),
                                    significant(record.depth->mtexelsPerSecond))
                      : significant(record.time->total);
}

std::string verificationCell(const Record& record) {
  if (!record.verification) return kMissing;
  const RecordVerification& v = *record.verification;
  std::string cell = fmt::format("{} / {}", formatTableNumber(double(v.queries), NumberKind::Count),
                                 formatTableNumber(double(v.mismatches), NumberKind::Integer));
  if (v.method == "sampled") cell += " (sampled)";
  if (v.mismatches > 0) cell += " FAIL";
  return cell;
}

// --- tables ---------------------------------------------------------------------------------

std::vector<std::string> resolutionHeader(std::string first,
                                          const std::set<uint64_t>& resolutions) {
  std::vector<std::string> header{std::move(first)};
  for (uint64_t r : resolutions) header.push_back(resolutionHeading(r));
  return header;
}

// One row per variant, one cell per resolution, "–" where there is no record.
template <typename CellText>
std::vector<std::string> variantRow(const Group& group, const Variant& variant, CellText cellText) {
  std::vector<std::string> row{variant.label()};
  for (uint64_t r : group.resolutions) {
    const Record* record = group.at(variant, r);
    row.push_back(record ? cellText(*record, r) : kMissing);
  }
  return row;
}

// The two size tables: our variants, then the analytic uncompressed shadow maps every scheme is
// measured against.
std::pair<Table, Table> sizeTables(const Group& group) {
  Table mibTable{
      "Size — " + group.describe(),
      "MiB (2^20 bytes), 3 significant digits; analytic rows: an uncompressed map of R² texels at "
      "2 or 4 bytes each; – = not built",
      resolutionHeader("scheme", group.resolutions),
      {},
      group.slug("size-mib")};
  Table percentTable{"Size relative to a 16-bit shadow map — " + group.describe(),
                     "% of R²·2 bytes at the same resolution, 3 significant digits; – = not built",
                     resolutionHeader("scheme", group.resolutions),
                     {},
                     group.slug("size-percent")};

  for (const Variant& v : group.variants) {
    mibTable.rows.push_back(variantRow(
        group, v, [](const Record& rec, uint64_t) { return mib(double(rec.sizeBytes)); }));
    percentTable.rows.push_back(variantRow(group, v, [](const Record& rec, uint64_t r) {
      return percentOf16Bit(double(rec.sizeBytes), r);
    }));
  }

  for (int bytesPerTexel : {2, 4}) {
    const std::string label = fmt::format("{}-bit shadow map (analytic)", bytesPerTexel * 8);
    std::vector<std::string> mibRow{label}, percentRow{label};
    for (uint64_t r : group.resolutions) {
      const double bytes = double(r) * double(r) * bytesPerTexel;
      mibRow.push_back(mib(bytes));
      percentRow.push_back(percentOf16Bit(bytes, r));
    }
    mibTable.rows.push_back(std::move(mibRow));
    percentTable.rows.push_back(std::move(percentRow));
  }
  return {std::move(mibTable), std::move(percentTable)};
}

// A table of one cell per variant and resolution, read from each record by `cell`.
Table perResolutionTable(const Group& group, const std::string& title, std::string unitNote,
                         std::string_view slugName, std::string (*cell)(const Record&)) {
  Table table{title + " — " + group.describe(),
              std::move(unitNote),
              resolutionHeader("scheme", group.resolutions),
              {},
              group.slug(slugName)};
  for (const Variant& v : group.variants)
    table.rows.push_back(
        variantRow(group, v, [cell](const Record& rec, uint64_t) { return cell(rec); }));
  return table;
}

Table buildTimeTable(const Group& group) {
  return perResolutionTable(
      group, "Build time",
      "seconds of wall time for the whole build, depth generation included; in parentheses the "
      "depth generation rate in Mtexels/s; – = not built or not timed",
      "build-time", buildTimeCell);
}

Table verificationTable(const Group& group) {
  return perResolutionTable(
      group, "Verification",
      "queries checked against the reference / mismatches; FAIL: not lossless; (sampled): random "
      "queries rather than every texel; – = not verified",
      "verification", verificationCell);
}

// The timings of one (query set, filter size) in a record's lookups.
const RecordLookup* lookupTiming(const Record& record, const std::string& querySet, int filter) {
  if (!record.lookup) return nullptr;
  for (const RecordLookup& t : *record.lookup)
    if (t.querySet == querySet && t.filter == filter) return &t;
  return nullptr;
}

// Two tables — one-thread latency and all-thread throughput — with a row per variant and
// resolution and a column per (query set, filter size). None when no record has timings.
std::vector<Table> lookupTables(const Group& group) {
  std::set<std::pair<std::string, int>> columns;
  std::set<uint64_t> threadCounts;
  for (const auto& [cell, record] : group.records)
    if (record->lookup)
      for (const RecordLookup& t : *record->lookup) {
        columns.insert({t.querySet, t.filter});
        threadCounts.insert(t.threads);
      }
  if (columns.empty()) return {};

  std::vector<std::string> header{"scheme", "resolution"};
  for (const auto& [set, k] : columns) header.push_back(fmt::format("{} {}×{}", set, k, k));
  Table latency{"Lookup time, one thread — " + group.describe(),
                "ns per query on one thread, by query set and PCF filter size k×k; – = not timed",
                header,
                {},
                group.slug("lookup-ns")};
  Table throughput{
      "Lookup throughput, all threads — " + group.describe(),
      fmt::format("Mqueries/s on all threads ({}), by query set and PCF filter size k×k; – = "
                  "not timed",
                  fmt::join(threadCounts, ", ")),
      header,
      {},
      group.slug("lookup-mqps")};
  for (const Variant& v : group.variants)
    for (uint64_t r : group.resolutions) {
      const Record* record = group.at(v, r);
      if (!record) continue;
      std::vector<std::string> ns{v.label(), resolutionHeading(r)}, mqps = ns;
      for (const auto& [set, k] : columns) {
        const RecordLookup* t = lookupTiming(*record, set, k);
        ns.push_back(t ? significant(t->nsPerQuerySingleThread) : kMissing);
        mqps.push_back(t ? significant(t->mqueriesPerSecondAllThreads) : kMissing);
      }
      latency.rows.push_back(std::move(ns));
      throughput.rows.push_back(std::move(mqps));
    }
  return {std::move(latency), std::move(throughput)};
}

template <typename Has>
bool anyRecordHas(const Group& group, Has has) {
  return std::any_of(group.records.begin(), group.records.end(),
                     [&](const auto& cell) { return has(*cell.second); });
}

std::vector<Table> tablesOf(const std::vector<const Record*>& shown) {
  std::vector<Table> tables;
  for (const Group& group : groupRecords(shown)) {
    auto [sizeMiB, sizePercent] = sizeTables(group);
    tables.push_back(std::move(sizeMiB));
    tables.push_back(std::move(sizePercent));
    if (anyRecordHas(group, [](const Record& r) { return r.time.has_value(); }))
      tables.push_back(buildTimeTable(group));
    if (anyRecordHas(group, [](const Record& r) { return r.verification.has_value(); }))
      tables.push_back(verificationTable(group));
    for (Table& t : lookupTables(group)) tables.push_back(std::move(t));
  }
  return tables;
}

// --- output ---------------------------------------------------------------------------------

std::string markdownCell(const std::string& cell) {
  std::string escaped;
  for (char c : cell) {
    if (c == '|')
      escaped += "\\|";
    else if (c == '\n' || c == '\r')
      escaped += ' ';
    else
      escaped += c;
  }
  return escaped;
}

std::string csvField(const std::string& field) {
  if (field.find_first_of(",\"\r\n") == std::string::npos) return field;
  std::string quoted = "\"";
  for (char c : field) quoted += c == '"' ? std::string("\"\"") : std::string(1, c);
  return quoted + "\"";
}

// Slugs made by this file are kept as they are; others are reduced to a safe name.
bool isFileNameSafe(const std::string& name) {
  return !name.empty() && name.front() != '.' && name.size() <= 200 &&
         std::all_of(name.begin(), name.end(), [](char c) {
           return (c >= 'a' && c <= 'z') || (c >= '0' && c <= '9') || c == '_' || c == '-' ||
                  c == '.';
         });
}

}  // namespace

std::string resolutionHeading(uint64_t resolution) {
  return resolution >= 1024 && resolution % 1024 == 0 ? fmt::format("{}K²", resolution / 1024)
                                                      : fmt::format("{}²", resolution);
}

std::vector<Table> makeTables(const std::vector<Record>& records) {
  return tablesOf(recordsShown(records, [](size_t, size_t, const std::string&) {}));
}

FolderTables tablesOfFolder(const fs::path& recordsDir) {
  const LoadedRecords loaded = readRecords(recordsDir);
  FolderTables result;
  for (const SkippedRecord& skipped : loaded.skipped)
    result.problems.push_back(fmt::format("skipped {}", skipped.reason));
  const auto shown =
      recordsShown(loaded.records, [&](size_t used, size_t unused, const std::string& why) {
        result.problems.push_back(fmt::format(
            "'{}' and '{}' are records of one table cell ({}, light {}, {}, {}, {}): the first is "
            "not used ({})",
            loaded.paths[unused].string(), loaded.paths[used].string(),
            loaded.records[used].scene.name, loaded.records[used].lightIndex,
            loaded.records[used].mode, variantOf(loaded.records[used]).label(),
            resolutionHeading(loaded.records[used].resolution), why));
        const std::string &usedSpec = loaded.records[used].scene.spec,
                          &unusedSpec = loaded.records[unused].scene.spec;
        if (usedSpec != unusedSpec)
          result.problems.back() += fmt::format(
              "; they come from the scene specs '{}' and '{}', whose scenes have one name",
              unusedSpec, usedSpec);
      });
  result.records = shown.size();
  result.tables = tablesOf(shown);
  return result;
}

std::string toMarkdown(const std::vector<Table>& tables) {
  std::string out;
  for (const Table& table : tables) {
    out += fmt::format("## {}\n\n", table.title);
    if (!table.unit_note.empty()) out += fmt::format("Unit: {}\n\n", table.unit_note);
    const auto line = [&](const std::vector<std::string>& cells) {
      out += "|";
      for (const std::string& cell : cells) {
        out += ' ';
        out += markdownCell(cell);
        out += " |";
      }
      out += "\n";
    };
    line(table.header);
    out += "|";
    for (size_t i = 0; i < table.header.size(); ++i) out += i == 0 ? " --- |" : " ---: |";
    out += "\n";
    for (const auto& row : table.rows) line(row);
    out += "\n";
  }
  return out;
}

std::string toCsv(const Table& table) {
  std::string out;
  const auto line = [&](const std::vector<std::string>& cells) {
    for (size_t i = 0; i < cells.size(); ++i) {
      if (i) out += ',';
      out += csvField(cells[i]);
    }
    out += "\r\n";
  };
  line(table.header);
  for (const auto& row : table.rows) line(row);
  return out;
}

void writeTables(const std::vector<Table>& tables, const fs::path& outDir) {
  std::set<std::string> written;
  for (const Table& table : tables) {
    const std::string base = isFileNameSafe(table.slug)
                                 ? table.slug
                                 : fileNamePart(table.slug.empty() ? table.title : table.slug);
    std::string slug = base;
    for (int n = 2; !written.insert(slug).second; ++n) slug = fmt::format("{}-{}", base, n);
    writeFileAtomically(outDir / (slug + ".csv"), toCsv(table));
  }
  writeFileAtomically(outDir / "tables.md", "# shadowbench tables\n\n" + toMarkdown(tables));
}

}  // namespace sb

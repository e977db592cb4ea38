#include "harness/table.h"

#include <algorithm>
#include <initializer_list>
#include <map>
#include <optional>
#include <set>
#include <tuple>

#include <fmt/format.h>

#include "harness/progress.h"
#include "harness/record.h"

namespace fs = std::filesystem;
using nlohmann::json;

namespace sb {

namespace {

const std::string kMissing = "–";
constexpr double kMiB = 1 << 20;
constexpr std::string_view kBaseline = "sm32";

// --- reading optional record fields ---------------------------------------------------------

const json* field(const json& record, std::initializer_list<const char*> path) {
  const json* at = &record;
  for (const char* key : path) {
    if (!at->is_object()) return nullptr;
    const auto it = at->find(key);
    if (it == at->end()) return nullptr;
    at = &*it;
  }
  return at;
}

std::optional<double> number(const json& record, std::initializer_list<const char*> path) {
  const json* value = field(record, path);
  if (!value || !value->is_number()) return std::nullopt;
  return value->get<double>();
}

std::string text(const json& record, std::initializer_list<const char*> path) {
  const json* value = field(record, path);
  return value && value->is_string() ? value->get<std::string>() : std::string();
}

uint64_t lightIndex(const json& record) {
  const json* value = field(record, {"light_index"});
  return value && value->is_number_integer() && value->get<int64_t>() >= 0 ? value->get<uint64_t>()
                                                                           : 0;
}

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

Variant variantOf(const json& record) {
  Variant variant{text(record, {"scheme", "name"}), {}};
  if (const json* params = field(record, {"scheme", "params"}); params && params->is_object())
    for (const auto& [name, value] : params->items())
      variant.params += fmt::format("{}{}={}", variant.params.empty() ? "" : ", ", name,
                                    value.is_string() ? value.get<std::string>() : value.dump());
  return variant;
}

// --- grouping -------------------------------------------------------------------------------

using Cell = std::pair<Variant, uint64_t>;  // (scheme with parameters, resolution)

// The records of one (scene, light index, mode): one table of each kind.
struct Group {
  std::string scene;
  uint64_t light = 0;
  std::string mode;
  std::set<std::string> specs;  // how the records named the scene on the command line
  std::map<Cell, const json*> newest;
  std::set<Variant> variants;
  std::set<uint64_t> resolutions;

  std::string describe() const { return fmt::format("{}, light {}, {}", scene, light, mode); }
  std::string slug(std::string_view kind) const {
    return fmt::format("{}_{}_{}_{}", kind, fileNamePart(scene), light, fileNamePart(mode));
  }
  const json* at(const Variant& v, uint64_t r) const {
    const auto it = newest.find({v, r});
    return it == newest.end() ? nullptr : it->second;
  }
};

std::vector<Group> groupRecords(const std::vector<json>& records) {
  std::map<std::tuple<std::string, uint64_t, std::string>, Group> groups;
  for (const json& record : records) {
    if (!isCompleteRecord(record)) continue;  // the tables read the required fields unchecked
    const std::string scene = text(record, {"scene", "name"}), mode = text(record, {"mode"});
    Group& group = groups[{scene, lightIndex(record), mode}];
    group.scene = scene, group.light = lightIndex(record), group.mode = mode;
    if (const std::string spec = text(record, {"scene", "spec"}); !spec.empty())
      group.specs.insert(spec);
    const Variant variant = variantOf(record);
    const uint64_t resolution = record["resolution"].get<uint64_t>();
    group.variants.insert(variant);
    group.resolutions.insert(resolution);
    // A re-run replaces an older record of its cell; of equal times the later path wins.
    const json*& kept = group.newest[{variant, resolution}];
    if (!kept || text(*kept, {"created"}) <= text(record, {"created"})) kept = &record;
  }
  std::vector<Group> ordered;
  for (auto& [key, group] : groups) ordered.push_back(std::move(group));
  return ordered;
}

bool figureMatches(const PaperFigure& figure, const Group& group) {
  if (figure.mode != group.mode) return false;
  const std::string generator = group.scene.substr(0, group.scene.find(':'));
  return figure.scene == group.scene || figure.scene == generator ||
         group.specs.count(figure.scene);
}

// --- cells ----------------------------------------------------------------------------------

std::string mib(double bytes) {
  return formatSignificant(bytes / kMiB);
}

double shadowMap16Bytes(uint64_t resolution) {
  return double(resolution) * double(resolution) * 2;
}

std::string percentOf16Bit(double bytes, uint64_t resolution) {
  return formatSignificant(100 * bytes / shadowMap16Bytes(resolution));
}

// "12.3M": a count with an SI prefix and no unit.
std::string count(double value) {
  std::string text = formatSi(value, "");
  text.erase(std::remove(text.begin(), text.end(), ' '), text.end());
  return text;
}

std::string buildTimeCell(const json& record) {
  const auto seconds = number(record, {"time_s", "total"});
  if (!seconds) return kMissing;
  const auto rate = number(record, {"depth", "mtexels_per_s"});
  return rate ? fmt::format("{} ({})", formatSignificant(*seconds), formatSignificant(*rate))
              : formatSignificant(*seconds);
}

std::string verificationCell(const json& record) {
  const auto queries = number(record, {"verification", "queries"});
  const auto mismatches = number(record, {"verification", "mismatches"});
  if (!queries || !mismatches) return kMissing;
  std::string cell = fmt::format("{} / {:.0f}", count(*queries), *mismatches);
  if (text(record, {"verification", "method"}) == "sampled") cell += " (sampled)";
  if (*mismatches > 0) cell += " FAIL";
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
    const json* record = group.at(variant, r);
    row.push_back(record ? cellText(*record, r) : kMissing);
  }
  return row;
}

// Paper figures of one label as a row over the group's resolutions.
template <typename CellText>
std::vector<std::string> paperRow(const Group& group, const std::string& label,
                                  const std::vector<const PaperFigure*>& figures,
                                  CellText cellText) {
  std::vector<std::string> row{label};
  for (uint64_t r : group.resolutions) {
    const auto it = std::find_if(figures.begin(), figures.end(), [&](const PaperFigure* f) {
      return f->label == label && f->resolution == r;
    });
    row.push_back(it == figures.end() ? kMissing : cellText((*it)->bytes, r));
  }
  return row;
}

// The two size tables: our variants, each followed by the paper's rows for its scheme, then
// the analytic uncompressed shadow maps every scheme is measured against.
std::pair<Table, Table> sizeTables(const Group& group,
                                   const std::vector<const PaperFigure*>& figures) {
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

  std::set<std::string, decltype(&schemeNameLess)> schemes(&schemeNameLess);
  for (const Variant& v : group.variants) schemes.insert(v.scheme);
  for (const PaperFigure* f : figures) schemes.insert(f->scheme);

  const auto bytesOf = [](const json& record) {
    return record["size_bytes"]["total"].get<double>();
  };
  for (const std::string& scheme : schemes) {
    for (const Variant& v : group.variants) {
      if (v.scheme != scheme) continue;
      mibTable.rows.push_back(
          variantRow(group, v, [&](const json& rec, uint64_t) { return mib(bytesOf(rec)); }));
      percentTable.rows.push_back(variantRow(
          group, v, [&](const json& rec, uint64_t r) { return percentOf16Bit(bytesOf(rec), r); }));
    }
    std::vector<std::string> labels;  // in the order given, each once
    for (const PaperFigure* f : figures)
      if (f->scheme == scheme && std::find(labels.begin(), labels.end(), f->label) == labels.end())
        labels.push_back(f->label);
    for (const std::string& label : labels) {
      mibTable.rows.push_back(
          paperRow(group, label, figures, [](double bytes, uint64_t) { return mib(bytes); }));
      percentTable.rows.push_back(paperRow(group, label, figures, percentOf16Bit));
    }
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
                         std::string_view slugName, std::string (*cell)(const json&)) {
  Table table{title + " — " + group.describe(),
              std::move(unitNote),
              resolutionHeader("scheme", group.resolutions),
              {},
              group.slug(slugName)};
  for (const Variant& v : group.variants)
    table.rows.push_back(
        variantRow(group, v, [cell](const json& rec, uint64_t) { return cell(rec); }));
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

// The timings of one (query set, filter size) in a record's "lookup" list.
const json* lookupTiming(const json& record, const std::string& querySet, int64_t filter) {
  const json* timings = field(record, {"lookup"});
  if (!timings || !timings->is_array()) return nullptr;
  for (const json& t : *timings)
    if (text(t, {"query_set"}) == querySet && field(t, {"filter"}) && t["filter"] == filter)
      return &t;
  return nullptr;
}

// Two tables — one-thread latency and all-thread throughput — with a row per variant and
// resolution and a column per (query set, filter size). None when no record has timings.
std::vector<Table> lookupTables(const Group& group) {
  std::set<std::pair<std::string, int64_t>> columns;
  std::set<int64_t> threadCounts;
  for (const auto& [cell, record] : group.newest)
    if (const json* timings = field(*record, {"lookup"}); timings && timings->is_array())
      for (const json& t : *timings) {
        const json* filter = field(t, {"filter"});
        if (text(t, {"query_set"}).empty() || !filter || !filter->is_number_integer()) continue;
        columns.insert({text(t, {"query_set"}), filter->get<int64_t>()});
        if (const auto threads = number(t, {"threads"})) threadCounts.insert(int64_t(*threads));
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
      const json* record = group.at(v, r);
      if (!record) continue;
      std::vector<std::string> ns{v.label(), resolutionHeading(r)}, mqps = ns;
      for (const auto& [set, k] : columns) {
        const json* t = lookupTiming(*record, set, k);
        const auto nsPerQuery = t ? number(*t, {"ns_per_query_1t"}) : std::nullopt;
        const auto mqueries = t ? number(*t, {"mqueries_per_s_all"}) : std::nullopt;
        ns.push_back(nsPerQuery ? formatSignificant(*nsPerQuery) : kMissing);
        mqps.push_back(mqueries ? formatSignificant(*mqueries) : kMissing);
      }
      latency.rows.push_back(std::move(ns));
      throughput.rows.push_back(std::move(mqps));
    }
  return {std::move(latency), std::move(throughput)};
}

bool anyRecordHas(const Group& group, const char* key) {
  return std::any_of(group.newest.begin(), group.newest.end(),
                     [&](const auto& cell) { return field(*cell.second, {key}) != nullptr; });
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

std::vector<Table> makeTables(const std::vector<json>& records,
                              std::span<const PaperFigure> paperFigures) {
  std::vector<Table> tables;
  for (Group& group : groupRecords(records)) {
    std::vector<const PaperFigure*> figures;
    for (const PaperFigure& f : paperFigures)
      if (f.resolution > 0 && figureMatches(f, group)) {
        figures.push_back(&f);
        group.resolutions.insert(f.resolution);  // the paper's sizes beside ours, even unbuilt
      }
    auto [sizeMiB, sizePercent] = sizeTables(group, figures);
    tables.push_back(std::move(sizeMiB));
    tables.push_back(std::move(sizePercent));
    if (anyRecordHas(group, "time_s")) tables.push_back(buildTimeTable(group));
    if (anyRecordHas(group, "verification")) tables.push_back(verificationTable(group));
    for (Table& t : lookupTables(group)) tables.push_back(std::move(t));
  }
  return tables;
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

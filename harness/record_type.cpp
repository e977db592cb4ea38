#include "harness/record_type.h"

#include <cmath>
#include <set>

#include <fmt/format.h>

#include "schemes/interface/lightspace.h"

using nlohmann::json;

namespace sb {

namespace {

// The fields of a record that this version reads; every other top-level field goes to `extra`.
const std::set<std::string, std::less<>> kKnownFields = {
    "format",      "complete",     "scene",
    "light_index", "light",        "mode",
    "scheme",      "resolution",   "depth_resolution",
    "tile_size",   "part_size",    "size_bytes",
    "time_s",      "depth",        "counters",
    "memory",      "verification", "lookup",
    "machine",     "commit",       "created"};

// A JSON object read field by field; errors name the field by its dotted path.
class Fields {
 public:
  Fields(const json& object, std::string path) : object_(object), path_(std::move(path)) {
    if (!object_.is_object())
      throw RecordError(fmt::format("{} is {}, not an object", where(), shown(object_)));
  }

  const json* find(std::string_view key) const {
    const auto it = object_.find(key);
    return it == object_.end() ? nullptr : &*it;
  }
  bool has(std::string_view key) const { return find(key) != nullptr; }
  const json& value() const { return object_; }

  const json& required(std::string_view key) const {
    if (const json* value = find(key)) return *value;
    throw RecordError(fmt::format("{} is missing", name(key)));
  }

  Fields object(std::string_view key) const { return Fields(required(key), name(key)); }

  std::string text(std::string_view key, bool isRequired = false) const {
    const json* value = isRequired ? &required(key) : find(key);
    if (!value) return {};
    if (!value->is_string())
      throw RecordError(fmt::format("{} is {}, not text", name(key), shown(*value)));
    return value->get<std::string>();
  }

  // A size or count: a non-negative integer (a JSON number without fraction).
  uint64_t count(std::string_view key, bool isRequired = false) const {
    const json* value = isRequired ? &required(key) : find(key);
    return value ? countValue(*value, name(key)) : 0;
  }

  // A time or rate: a finite non-negative number.
  double amount(std::string_view key) const {
    const json* value = find(key);
    return value ? amountValue(*value, name(key)) : 0;
  }

  std::string name(std::string_view key) const {
    return path_.empty() ? std::string(key) : fmt::format("{}.{}", path_, key);
  }

  static uint64_t countValue(const json& value, const std::string& name) {
    if (value.is_number_unsigned()) return value.get<uint64_t>();
    if (value.is_number_integer()) {
      if (value.get<int64_t>() >= 0) return value.get<uint64_t>();
      throw RecordError(fmt::format("{} is {}: it cannot be negative", name, shown(value)));
    }
    if (value.is_number_float()) {
      const double number = value.get<double>();
      if (number >= 0 && number < 0x1p64 && number == std::floor(number)) return uint64_t(number);
      throw RecordError(
          fmt::format("{} is {}: it must be a non-negative integer", name, shown(value)));
    }
    throw RecordError(fmt::format("{} is {}, not a number", name, shown(value)));
  }

  static double amountValue(const json& value, const std::string& name) {
    if (!value.is_number())
      throw RecordError(fmt::format("{} is {}, not a number", name, shown(value)));
    const double number = value.get<double>();
    if (!(number >= 0) || !std::isfinite(number))
      throw RecordError(fmt::format("{} is {}: it cannot be negative", name, shown(value)));
    return number;
  }

  // At most 40 characters of the value, for messages.
  static std::string shown(const json& value) {
    std::string text = value.dump(-1, ' ', false, json::error_handler_t::replace);
    return text.size() > 40 ? text.substr(0, 37) + "..." : text;
  }

 private:
  std::string where() const { return path_.empty() ? "the record" : path_; }

  const json& object_;
  std::string path_;
};

template <typename Value, typename Read>
std::map<std::string, Value> mapOf(const Fields& parent, std::string_view key, Read read) {
  std::map<std::string, Value> values;
  const json* object = parent.find(key);
  if (!object) return values;
  const std::string path = parent.name(key);
  for (const auto& [name, value] : Fields(*object, path).value().items())
    values[name] = read(value, fmt::format("{}.{}", path, name));
  return values;
}

uint32_t resolutionOf(const Fields& record) {
  const uint64_t resolution = record.count("resolution", true);
  if (!validResolution(resolution))
    throw RecordError(fmt::format("resolution is {}: it must be a power of two from {} to {}",
                                  resolution, kMinResolution, kMaxResolution));
  return uint32_t(resolution);
}

uint32_t smallCount(const Fields& fields, std::string_view key) {
  const uint64_t value = fields.count(key);
  if (value > UINT32_MAX)
    throw RecordError(fmt::format("{} is {}: too large", fields.name(key), value));
  return uint32_t(value);
}

// An optional list of scheme names.
std::vector<std::string> schemeNames(const Fields& parent, std::string_view key) {
  std::vector<std::string> names;
  const json* list = parent.find(key);
  if (!list) return names;
  if (!list->is_array())
    throw RecordError(fmt::format("{} is {}, not a list", parent.name(key), Fields::shown(*list)));
  for (const json& name : *list) {
    if (!name.is_string())
      throw RecordError(
          fmt::format("{} holds {}, not a scheme name", parent.name(key), Fields::shown(name)));
    names.push_back(name.get<std::string>());
  }
  return names;
}

RecordLookup lookupOf(const json& value, const std::string& path) {
  const Fields t(value, path);
  RecordLookup lookup;
  lookup.querySet = t.text("query_set", true);
  const uint64_t filter = t.count("filter", true);
  if (filter % 2 == 0 || filter > 17)
    throw RecordError(fmt::format("{} is {}: filters are odd, 1 to 17", t.name("filter"), filter));
  lookup.filter = int(filter);
  lookup.queries = t.count("queries");
  lookup.nsPerQuerySingleThread = t.amount("ns_per_query_1t");
  lookup.mqueriesPerSecondAllThreads = t.amount("mqueries_per_s_all");
  lookup.threads = t.count("threads");
  if (t.has("cache_hit_rate")) {
    lookup.cacheHitRate = t.amount("cache_hit_rate");
    if (*lookup.cacheHitRate > 1)
      throw RecordError(fmt::format("{} is {}: a share, at most 1", t.name("cache_hit_rate"),
                                    *lookup.cacheHitRate));
  }
  return lookup;
}

}  // namespace

void to_json(json& j, const Record& r) {
  j = r.extra.is_object() ? r.extra : json::object();
  j["format"] = r.format;
  j["complete"] = r.complete;
  j["scene"] = {{"name", r.scene.name},
                {"spec", r.scene.spec},
                {"triangles", r.scene.triangles},
                {"hash", r.scene.hash}};
  j["light_index"] = r.lightIndex;
  if (!r.light.is_null()) j["light"] = r.light;
  j["mode"] = r.mode;
  j["scheme"] = {{"name", r.scheme.name},
                 {"kind", r.scheme.kind},
                 {"params", r.scheme.params},
                 {"paper", r.scheme.paper}};
  j["resolution"] = r.resolution;
  j["depth_resolution"] = r.depthResolution;
  j["tile_size"] = r.tileSize;
  if (r.partSize) j["part_size"] = r.partSize;
  j["size_bytes"] = {{"total", r.sizeBytes}, {"components", r.sizeComponents}};
  if (r.time) {
    j["time_s"] = {{"total", r.time->total}, {"depth", r.time->depth}, {"phases", r.time->phases}};
    if (!r.time->depthSharedWith.empty())
      j["time_s"]["depth_shared_with"] = r.time->depthSharedWith;
    if (!r.time->encoderSharedWith.empty())
      j["time_s"]["encoder_shared_with"] = r.time->encoderSharedWith;
  }
  if (r.depth)
    j["depth"] = {{"texels", r.depth->texels},
                  {"mtexels_per_s", r.depth->mtexelsPerSecond},
                  {"closed_fallbacks", r.depth->closedFallbacks},
                  {"method", r.depth->method}};
  j["counters"] = r.counters;
  if (r.memory) {
    j["memory"] = {{"peak_rss_bytes", r.memory->peakRssBytes},
                   {"baseline_rss_bytes", r.memory->baselineRssBytes}};
    if (r.memory->estimatedBytes) j["memory"]["estimated_bytes"] = r.memory->estimatedBytes;
    for (const auto& [key, step] :
         {std::pair{"parts", &r.memory->parts}, {"merge", &r.memory->merge}})
      if (*step) {
        j["memory"][key] = {{"peak_rss_bytes", (*step)->peakRssBytes}};
        if ((*step)->estimatedBytes) j["memory"][key]["estimated_bytes"] = (*step)->estimatedBytes;
      }
  }
  if (r.verification)
    j["verification"] = {{"method", r.verification->method},
                         {"queries", r.verification->queries},
                         {"mismatches", r.verification->mismatches},
                         {"examples", r.verification->examples}};
  if (r.lookup) {
    json list = json::array();
    for (const RecordLookup& t : *r.lookup) {
      list.push_back({{"query_set", t.querySet},
                      {"filter", t.filter},
                      {"queries", t.queries},
                      {"ns_per_query_1t", t.nsPerQuerySingleThread},
                      {"mqueries_per_s_all", t.mqueriesPerSecondAllThreads},
                      {"threads", t.threads}});
      if (t.cacheHitRate) list.back()["cache_hit_rate"] = *t.cacheHitRate;
    }
    j["lookup"] = std::move(list);
  }
  if (!r.machine.is_null()) j["machine"] = r.machine;
  if (!r.commit.empty()) j["commit"] = r.commit;
  if (!r.created.empty()) j["created"] = r.created;
}

void from_json(const json& j, Record& out) {
  const Fields top(j, "");
  Record r;
  r.format = top.text("format", true);
  if (r.format != kRecordFormat)
    throw RecordError(fmt::format("format is '{}', not '{}'", r.format, kRecordFormat));
  const json& complete = top.required("complete");
  if (!complete.is_boolean() || !complete.get<bool>())
    throw RecordError(
        fmt::format("complete is {}: the record was cut short", Fields::shown(complete)));
  r.complete = true;

  const Fields scene = top.object("scene");
  r.scene = {scene.text("name", true), scene.text("spec"), scene.count("triangles"),
             scene.text("hash")};
  r.lightIndex = smallCount(top, "light_index");
  if (top.has("light")) r.light = top.object("light").value();
  r.mode = top.text("mode", true);
  if (r.mode != "open" && r.mode != "closed" && r.mode != "static")
    throw RecordError(fmt::format("mode is '{}': it must be open, closed or static", r.mode));

  const Fields scheme = top.object("scheme");
  r.scheme.name = scheme.text("name", true);
  if (r.scheme.name.empty()) throw RecordError("scheme.name is empty");
  r.scheme.kind = scheme.text("kind");
  r.scheme.paper = scheme.text("paper");
  r.scheme.params = mapOf<std::string>(scheme, "params", [](const json& v, const std::string& p) {
    // Older writers may have stored numbers; the text is what names the parameter's value.
    if (v.is_string()) return v.get<std::string>();
    if (v.is_number()) return v.dump();
    throw RecordError(fmt::format("{} is {}, not text", p, Fields::shown(v)));
  });

  r.resolution = resolutionOf(top);
  r.depthResolution = smallCount(top, "depth_resolution");
  r.tileSize = smallCount(top, "tile_size");
  r.partSize = smallCount(top, "part_size");
  const Fields size = top.object("size_bytes");
  r.sizeBytes = size.count("total", true);
  r.sizeComponents = mapOf<uint64_t>(size, "components", Fields::countValue);

  if (top.has("time_s")) {
    const Fields time = top.object("time_s");
    r.time = RecordTimes{time.amount("total"), time.amount("depth"),
                         mapOf<double>(time, "phases", Fields::amountValue),
                         schemeNames(time, "depth_shared_with"),
                         schemeNames(time, "encoder_shared_with")};
  }
  if (top.has("depth")) {
    const Fields depth = top.object("depth");
    r.depth = RecordDepth{depth.count("texels"), depth.amount("mtexels_per_s"),
                          depth.count("closed_fallbacks"), depth.text("method")};
  }
  r.counters = mapOf<uint64_t>(top, "counters", Fields::countValue);
  if (top.has("memory")) {
    const Fields memory = top.object("memory");
    r.memory.emplace();
    r.memory->peakRssBytes = memory.count("peak_rss_bytes");
    r.memory->baselineRssBytes = memory.count("baseline_rss_bytes");
    r.memory->estimatedBytes = memory.count("estimated_bytes");
    for (const auto& [key, step] :
         {std::pair{"parts", &r.memory->parts}, {"merge", &r.memory->merge}})
      if (memory.has(key)) {
        const Fields fields = memory.object(key);
        *step =
            RecordMemoryStep{fields.count("estimated_bytes"), fields.count("peak_rss_bytes", true)};
      }
  }
  if (top.has("verification")) {
    const Fields v = top.object("verification");
    RecordVerification verification{v.text("method", true), v.count("queries", true),
                                    v.count("mismatches", true), json::array()};
    if (const json* examples = v.find("examples")) {
      if (!examples->is_array())
        throw RecordError(
            fmt::format("verification.examples is {}, not a list", Fields::shown(*examples)));
      verification.examples = *examples;
    }
    r.verification = std::move(verification);
  }
  if (const json* lookup = top.find("lookup")) {
    if (!lookup->is_array())
      throw RecordError(fmt::format("lookup is {}, not a list", Fields::shown(*lookup)));
    r.lookup.emplace();
    for (size_t i = 0; i < lookup->size(); ++i)
      r.lookup->push_back(lookupOf((*lookup)[i], fmt::format("lookup[{}]", i)));
  }
  if (top.has("machine")) r.machine = top.object("machine").value();
  r.commit = top.text("commit");
  r.created = top.text("created");
  for (const auto& [key, value] : j.items())
    if (!kKnownFields.count(key)) r.extra[key] = value;
  out = std::move(r);
}

}  // namespace sb

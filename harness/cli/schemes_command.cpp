#include <memory>
#include <string>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "harness/cli/commands.h"
#include "schemes/interface/scheme.h"

namespace sb::cli {

namespace {

void listSchemes() {
  for (const SchemeInfo& s : schemes()) {
    fmt::print("{:12} {} scheme — {}\n", s.name, toString(s.kind), s.paper);
    for (const ParamSpec& p : s.params)
      fmt::print("    {}={} ({}{}) {}\n", p.name, p.defaultValue,
                 p.choices.empty() ? fmt::format("{}…{}", p.min, p.max)
                                   : fmt::format("{}", fmt::join(p.choices, "|")),
                 p.sweep.empty() ? "" : fmt::format("; sweep {}", fmt::join(p.sweep, ",")), p.help);
  }
}

// The registry for scripts (plot.py, paper_tables.py), in the format of the issue 11
// interface: values are strings, as records store parameter values.
nlohmann::ordered_json paramJson(const ParamSpec& p) {
  nlohmann::ordered_json param = {{"name", p.name},
                                  {"help", p.help},
                                  {"type", p.choices.empty() ? "integer" : "choice"},
                                  {"default", p.defaultValue}};
  if (p.choices.empty()) {
    param["min"] = p.min;
    param["max"] = p.max;
  } else {
    param["choices"] = p.choices;
  }
  param["sweep"] = p.sweep;
  return param;
}

void printSchemesJson() {
  nlohmann::ordered_json list = nlohmann::ordered_json::array();
  for (const SchemeInfo& s : schemes()) {
    nlohmann::ordered_json params = nlohmann::ordered_json::array();
    for (const ParamSpec& p : s.params) params.push_back(paramJson(p));
    list.push_back({{"name", s.name},
                    {"kind", std::string(toString(s.kind))},
                    {"paper", s.paper},
                    {"params", std::move(params)}});
  }
  fmt::print("{}\n", nlohmann::ordered_json{{"schemes", std::move(list)}}.dump(2));
}

}  // namespace

void addSchemesCommand(CLI::App& app) {
  auto json = std::make_shared<bool>(false);
  CLI::App* sub = app.add_subcommand("schemes", "list registered schemes and their parameters");
  sub->add_flag("--json", *json, "print the registry as JSON (names, kinds, parameters)");
  sub->callback([json] { *json ? printSchemesJson() : listSchemes(); });
}

}  // namespace sb::cli

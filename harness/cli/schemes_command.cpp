#include <fmt/format.h>

#include "harness/cli/commands.h"
#include "schemes/interface/scheme.h"

namespace sb::cli {

void addSchemesCommand(CLI::App& app) {
  app.add_subcommand("schemes", "list registered schemes and their parameters")->callback([] {
    for (const SchemeInfo& s : schemes()) {
      fmt::print("{:12} {} scheme — {}\n", s.name, toString(s.kind), s.paper);
      for (const ParamSpec& p : s.params)
        fmt::print("    {}={} ({}{}) {}\n", p.name, p.defaultValue,
                   p.choices.empty() ? fmt::format("{}…{}", p.min, p.max)
                                     : fmt::format("{}", fmt::join(p.choices, "|")),
                   p.sweep.empty() ? "" : fmt::format("; sweep {}", fmt::join(p.sweep, ",")),
                   p.help);
    }
  });
}

}  // namespace sb::cli

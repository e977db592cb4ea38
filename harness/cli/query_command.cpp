#include <iostream>
#include <memory>
#include <optional>

#include <fmt/format.h>

#include "harness/cli/commands.h"
#include "harness/cli/options.h"
#include "harness/query_line.h"
#include "schemes/interface/serial.h"

namespace sb::cli {

namespace {

void answerQueries(const std::string& structure) {
  const auto decoder = loadStructure(structure, nullptr);
  std::string line;
  for (uint64_t number = 1; std::getline(std::cin, line); ++number) {
    const std::optional<QueryLine> parsed = parseQueryLine(line, number);
    if (!parsed) continue;
    float visibility = 0;
    decoder->lookup(std::span(&parsed->query, 1), parsed->filter, std::span(&visibility, 1));
    fmt::print("{}\n", visibility);
    // Each answer is flushed: a program that writes a query and waits gets its answer, and the
    // first answer that cannot be written ends the run instead of computing more to lose.
    flushStandardOutput();
  }
}

}  // namespace

void addQueryCommand(CLI::App& app) {
  auto structure = std::make_shared<std::string>();
  CLI::App* sub =
      app.add_subcommand("query", "answer 'x y z [k]' lines from stdin with a saved structure");
  sub->add_option("structure", *structure, "structure file")->required();
  sub->callback([structure] { answerQueries(*structure); });
}

}  // namespace sb::cli

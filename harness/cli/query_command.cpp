#include <iostream>
#include <memory>
#include <sstream>

#include <fmt/format.h>

#include "harness/cli/commands.h"
#include "harness/cli/options.h"
#include "schemes/interface/serial.h"

namespace sb::cli {

namespace {

void answerQueries(const std::string& structure) {
  const auto decoder = loadStructure(structure, nullptr);
  std::string line;
  for (uint64_t number = 1; std::getline(std::cin, line); ++number) {
    std::istringstream in(line);
    Query q{};
    int k = 1;
    if (!(in >> q.x >> q.y >> q.z)) {
      if (line.find_first_not_of(" \t\r") == std::string::npos) continue;
      throw std::invalid_argument(
          fmt::format("query line {}: expected 'x y z [k]', got '{}'", number, line));
    }
    in >> k;
    float visibility = 0;
    decoder->lookup(std::span(&q, 1), k, std::span(&visibility, 1));
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

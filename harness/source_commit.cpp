#include "harness/source_commit.h"

#include <sys/wait.h>

#include <cstdio>
#include <optional>

namespace fs = std::filesystem;

namespace sb {

namespace {

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

}  // namespace

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

}  // namespace sb

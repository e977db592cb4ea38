// The commit of the source a record was built from (DESIGN §6).
#pragma once

#include <filesystem>
#include <string>

namespace sb {

// The commit of the checkout at `sourceDir` (12 hex digits), with "-dirty" when tracked files
// differ from it; "unknown" when git or the repository is missing. Never throws.
std::string sourceCommit(const std::filesystem::path& sourceDir);

}  // namespace sb

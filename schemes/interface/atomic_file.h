// Writing a file so that it holds either its old contents or all the new ones, never a part:
// the one atomic writer of the project (records, tables, structure files).
#pragma once

#include <filesystem>
#include <string_view>

namespace sb {

// Writes `contents` to `path` through a unique temporary in the same folder, fsync, rename;
// creates parent folders. Refuses (before writing anything) a `path` that exists and is not a
// regular file: a rename would replace a device node, a folder or a FIFO with a plain file.
// Throws std::runtime_error naming the path on failure and leaves no temporary behind.
void writeFileAtomically(const std::filesystem::path& path, std::string_view contents);

// Throws std::runtime_error unless `path` is absent or a regular file (a symbolic link counts
// as what it points to): what writeFileAtomically checks first, for callers that want to refuse
// an output before spending time on what they will write.
void checkReplaceable(const std::filesystem::path& path);

// Creates `folder` ("" is the current folder) and creates and removes a file in it, so that a
// folder where nothing can be written is found before the work whose output would go there.
// Throws std::runtime_error naming the folder.
void checkWritableFolder(const std::filesystem::path& folder);

}  // namespace sb

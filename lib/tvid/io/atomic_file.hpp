#pragma once
// Files written whole or not at all: the content goes to a temporary name in the same
// folder, is flushed to disk, and is renamed over the target (rename is atomic on POSIX),
// so a crash, Ctrl-C or kill never leaves a torn file.

#include <filesystem>
#include <string_view>

namespace tvid {

/// The temporary file's name is the target's + this + the process id ("params.json.tvid-tmp.4242"):
/// distinct enough that clearing a killed run's leftovers never touches a user's file.
inline constexpr const char* kAtomicTemporaryMarker = ".tvid-tmp.";

/// Throws std::runtime_error naming the path when the file cannot be written.
void write_file_atomically(const std::filesystem::path& path, std::string_view content);

}  // namespace tvid

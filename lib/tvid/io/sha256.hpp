#pragma once
// SHA-256 of a file, for the provenance fields of summary.json.

#include <filesystem>
#include <string>

namespace tvid {

/// Lower-case hex digest; throws std::runtime_error when the file cannot be read.
std::string sha256_of_file(const std::filesystem::path& file);

}  // namespace tvid

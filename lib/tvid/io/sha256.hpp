#pragma once
// SHA-256 of a file or of bytes read from one, for the provenance fields of summary.json
// and the batch record.

#include <filesystem>
#include <string>
#include <string_view>

namespace tvid {

/// Lower-case hex digest; throws std::runtime_error when the file cannot be read.
std::string sha256_of_file(const std::filesystem::path& file);

/// Lower-case hex digest of bytes already read (what was read is what is recorded).
std::string sha256_of_text(std::string_view text);

}  // namespace tvid

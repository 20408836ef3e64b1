#pragma once
// Where a fit report goes, checked before any work is done: a directory that already
// holds a report is not overwritten unless asked (`--force`), an unwritable place is bad
// input rather than a failure after a long fit, and temporary files that a killed run left
// behind (the atomic writes' `NAME.tvid-tmp.PID`) are swept away.

#include <filesystem>

#include "tvid/io/output_directory.hpp"

namespace tvid {

/// Creates `dir` if needed and makes sure a report can be written there. Throws InputError
/// (exit status 2) when `dir` is a file, cannot be created or written, or already holds a
/// fit report (summary.json or params.json) and `force` is false, or another run holds it.
/// Keep the returned lock until the report is written.
[[nodiscard]] OutputDirectoryLock prepare_report_directory(const std::filesystem::path& dir, bool force);

}  // namespace tvid

#pragma once
// Where a fit report goes, checked before any work is done. A report tvid wrote there for
// the same experiment is replaced (running the same command again just works); a report of
// another experiment, or a file tvid did not write under one of its report's names, is not
// overwritten unless asked (`--force`); files of other names are never touched. An
// unwritable place is bad input rather than a failure after a long fit, and temporary files
// that a killed run left behind (the atomic writes' `NAME.tvid-tmp.PID`) are swept away.

#include <filesystem>
#include <string>
#include <vector>

#include "tvid/experiment/experiment.hpp"
#include "tvid/io/output_directory.hpp"

namespace tvid {

/// Where the report of `experiment` goes: `output_dir` (-o) when given, else the
/// experiment's report.dir, else results/NAME.
std::filesystem::path report_directory(const Experiment& experiment, const std::string& output_dir);

/// Every file a fit report may hold (write_fit_report writes these names and no other).
const std::vector<std::string>& fit_report_files();

/// Creates `dir` if needed and makes sure a report can be written there. Throws InputError
/// (exit status 2) when `dir` is a file, cannot be created or written, or another run holds
/// it; and, unless `force`, when it holds params.json or summary.json that are not a tvid
/// report of `experiment` (summary.json, the report's manifest, names the tool and the
/// experiment), or when one of fit_report_files() there is not a regular file or is a file
/// the run reads (the recording named estimation.csv, in the folder the report goes to).
/// Keep the returned lock until the report is written.
[[nodiscard]] OutputDirectoryLock prepare_report_directory(const std::filesystem::path& dir, bool force,
                                                           const std::string& experiment);

}  // namespace tvid

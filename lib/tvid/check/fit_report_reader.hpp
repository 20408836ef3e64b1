#pragma once
// Reading back the report directory of `tvid fit` (summary.json, params.json), as
// `tvid check` does. Only the files' presence and shape are checked here.

#include <filesystem>
#include <string>

#include <nlohmann/json.hpp>

namespace tvid {

struct FitReportFiles {
    std::filesystem::path dir;
    nlohmann::json summary;  ///< summary.json
    nlohmann::json params;   ///< params.json

    std::string summary_file() const { return (dir / "summary.json").string(); }
    std::string params_file() const { return (dir / "params.json").string(); }
};

/// Throws InputError naming the file and key when `dir` is missing, incomplete (no
/// summary.json: it is written last) or not a tvid fit report.
FitReportFiles read_fit_report(const std::filesystem::path& dir);

}  // namespace tvid

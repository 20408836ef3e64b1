#pragma once
// The report directory of a fit (docs/report-format.md): params.json,
// params.csv, summary.json, estimation.csv, validation.csv, history.csv. Every file is
// written to a temporary name and renamed.

#include <filesystem>
#include <string>

#include <nlohmann/json.hpp>

#include "tvid/analysis/identifiability.hpp"
#include "tvid/fit/fit_run.hpp"

namespace tvid {

struct RunContext {
    std::string version;       ///< tool version
    std::string command_line;  ///< as typed
};

/// Creates `dir` if needed and writes every report file. Throws std::runtime_error when
/// the directory or a file cannot be written.
void write_fit_report(const std::filesystem::path& dir, const IdentificationProblem& problem, const FitResult& fit,
                      const RunContext& context);

/// summary.json's content (also printed by `--json`).
nlohmann::json fit_summary_json(const IdentificationProblem& problem, const FitResult& fit, const RunContext& context);

/// summary.json's `verdict` block (also a batch row's).
nlohmann::json verdict_json(const Verdict& verdict);

/// summary.json's `identifiability` block.
nlohmann::json identifiability_json(const IdentifiabilityReport& report);

/// params.json's content.
nlohmann::json parameters_json(const IdentificationProblem& problem, const FitResult& fit);

/// The metrics of one split as JSON (pooled per output, and per window).
nlohmann::json split_json(const Experiment& experiment, const SplitEvaluation& split);

/// estimation.csv / validation.csv content: t, window, and per output measured,
/// simulated, residual (measured − simulated) and residual ratio.
std::string trace_csv(const Experiment& experiment, const SplitEvaluation& split);

}  // namespace tvid

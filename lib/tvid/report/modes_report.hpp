#pragma once
// The report of `tvid modes` (modes.csv, modes.json and the terminal's table), the
// `modes` block of a fit's summary.json, and the report of `tvid frf` (frf.csv, frf.json).

#include <filesystem>
#include <string>

#include <nlohmann/json.hpp>

#include "tvid/analysis/frf_comparison.hpp"
#include "tvid/analysis/torsional_modes.hpp"

namespace tvid {

/// How a report was made, for its JSON.
struct ModesRunInfo {
    std::string version;
    std::string command_line;
    std::string experiment;  ///< the experiment's name
    std::string model;       ///< its preset, or "custom"
};

/// modes.json: the operating point, how each element was linearised, every mode with its shape.
nlohmann::json modes_json(const ModesStudy& study, const ModesRunInfo& run);

/// summary.json's `modes` block: the operating point, and per mode kind, frequency_hz,
/// damped_frequency_hz, damping_ratio and shape {node: Re of the normalised shape}.
nlohmann::json modes_summary_json(const ModesStudy& study);

/// summary.json's `modes` block of a fit at its parameters `params` (linearised at the
/// first estimation window's start), or null when the model cannot be linearised there.
nlohmann::json fit_modes_json(const IdentificationProblem& problem, const std::vector<double>& params,
                              const SolvedStart* start = nullptr);

/// modes.csv: one row per mode, then per node its shape (real part, magnitude, phase) and
/// the shape referred to the reference node's shaft.
std::string modes_csv(const ModesStudy& study);

/// The terminal's table: mode, kind, f_n, f_d, ζ, dominant node.
std::string modes_table_text(const ModesStudy& study);

/// Writes modes.csv, then modes.json, into `dir` (created if needed).
void write_modes_report(const std::filesystem::path& dir, const ModesStudy& study, const ModesRunInfo& run);

/// frf.json: input, output, units, the operating point, the Welch settings and every row.
nlohmann::json frf_json(const FrfComparison& frf, const ModesRunInfo& run);

/// frf.csv: frequency_hz, the model's magnitude and phase, the measured H1's and the coherence.
std::string frf_csv(const FrfComparison& frf);

/// Writes frf.csv, then frf.json, into `dir` (created if needed).
void write_frf_report(const std::filesystem::path& dir, const FrfComparison& frf, const ModesRunInfo& run);

/// The terminal's lines for an FRF: the largest model peaks and the measured ones near them.
std::string frf_summary_text(const FrfComparison& frf);

}  // namespace tvid

#pragma once
// The report of `tvid sensitivity` (the methodology paper Figs. 4–5: how the output responds to each
// parameter): sensitivity.csv (∂y/∂p_j and the scaled sensitivity p_j·∂y/∂p_j at every
// scored sample), ranking.csv (the free parameters of each output ranked by the RMS of
// p_j·∂y/∂p_j) and sensitivity.json. Built from the forward sensitivities of the windows;
// every file is written to a temporary name and renamed.

#include <cstddef>
#include <filesystem>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "tvid/estimation/forward_sensitivity.hpp"

namespace tvid {

/// The sensitivities of one parameter set over a list of windows, and what they refer to.
struct SensitivityStudy {
    std::string experiment;                        ///< experiment name
    std::string model;                             ///< preset name, or "custom"
    std::vector<std::string> parameters;           ///< every model parameter, in model order
    std::vector<double> values;                    ///< the values used, one per model parameter
    std::vector<std::size_t> free;                 ///< indices into `parameters` of the free ones, in dydp order
    std::vector<std::string> outputs;              ///< compared outputs, in WindowSensitivity::output order
    std::vector<WindowSensitivity> estimation;     ///< estimation windows, in experiment order
    std::vector<WindowSensitivity> validation;     ///< validation windows (empty unless asked for)
    /// Each recording's name by Window::recording, with data.recordings (else empty); the
    /// windows' times are on their recordings' own clocks.
    std::vector<std::string> recordings;

    std::size_t samples() const;                   ///< scored samples over all windows
};

/// The study of `problem` at the full parameter vector `values` (problem.full_parameters order).
SensitivityStudy make_sensitivity_study(const IdentificationProblem& problem, const std::vector<double>& values,
                                        std::vector<WindowSensitivity> estimation,
                                        std::vector<WindowSensitivity> validation);

/// One free parameter's place in an output's ranking.
struct ParameterRank {
    int rank = 0;                  ///< 1 = the largest scaled sensitivity
    std::size_t free_index = 0;    ///< position among the free parameters
    std::string parameter;
    double value = 0.0;            ///< p_j
    double rms_scaled = 0.0;       ///< √(mean_k (p_j ∂y/∂p_j)²): output change for a 100 % change of p_j
    double rms_raw = 0.0;          ///< √(mean_k (∂y/∂p_j)²), output unit per parameter unit
    double relative = 0.0;         ///< rms_scaled / the largest rms_scaled of the output; NaN if that is 0
};

struct OutputRanking {
    std::string output;
    std::size_t samples = 0;             ///< scored samples the RMS runs over
    std::vector<ParameterRank> ranks;    ///< every free parameter, largest rms_scaled first
};

/// Per output, the free parameters ranked by the RMS of the scaled sensitivity over every
/// scored sample of every window of the study. Ties keep the parameter order.
std::vector<OutputRanking> rank_parameters(const SensitivityStudy& study);

/// sensitivity.csv: `window,time,output,y`, then `d_P` = ∂y/∂P and `s_P` = P·∂y/∂P for
/// every free parameter P; one row per scored sample and output.
std::string sensitivity_csv(const SensitivityStudy& study);

/// ranking.csv: `output,rank,parameter,value,rms_scaled,relative,rms_raw`.
std::string ranking_csv(const std::vector<OutputRanking>& rankings);

/// How the study was run, for sensitivity.json.
struct SensitivityRunInfo {
    std::string version;        ///< tool version
    std::string command_line;   ///< as typed
    int threads = 1;
    double wall_seconds = 0.0;  ///< the sensitivity simulations
};

/// sensitivity.json: experiment, model, parameter values, windows, ranking, run info.
nlohmann::json sensitivity_json(const SensitivityStudy& study, const std::vector<OutputRanking>& rankings,
                                const SensitivityRunInfo& run);

/// Creates `dir` if needed and writes sensitivity.csv, ranking.csv and, last,
/// sensitivity.json. Throws std::runtime_error naming the path when it cannot.
void write_sensitivity_report(const std::filesystem::path& dir, const SensitivityStudy& study,
                              const std::vector<OutputRanking>& rankings, const SensitivityRunInfo& run);

}  // namespace tvid

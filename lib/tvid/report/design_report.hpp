#pragma once
// The report of `tvid design --evaluate` (docs/experiment-design.md): each candidate
// input's predicted standard errors and correlations, the assumptions the prediction
// rests on (local at the nominal values, the noise model, the operating point), and each
// generated reference input as a CSV a bench controller can play.

#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "tvid/design/design_spec.hpp"
#include "tvid/design/multisine_design.hpp"
#include "tvid/design/parameter_draws.hpp"
#include "tvid/design/predicted_uncertainty.hpp"
#include "tvid/experiment/experiment.hpp"

namespace tvid {

/// A candidate input and its prediction.
struct DesignCandidate {
    std::string name;             ///< "designed", "given", "multisine", "chirp", "prbs"
    std::string source;           ///< where it came from: a CSV file and column, or how it was generated
    std::string file;             ///< the CSV this report writes for it ("" for a given input)
    std::vector<double> time;
    std::vector<double> value;    ///< the designed input, in its channel's unit
    PredictedUncertainty prediction;
    /// With design.robust: the criterion at each drawn parameter set, and the criterion
    /// averaged over the nominal set and the draws (what ranks the candidates then).
    std::vector<double> draw_criteria;
    double robust_criterion = 0.0;
    const MultisineDesign* search = nullptr;  ///< the designed input's search, for its report
};

struct DesignRunInfo {
    std::string version;
    std::string command_line;
    std::string nominal_source;   ///< "init" or the parameter file read
    int threads = 1;
    double wall_seconds = 0.0;
};

/// design.json: the assumptions (the nominal values, sets[0], and any drawn sets), the design
/// section, each candidate's prediction, and the candidate the criterion ranks first.
nlohmann::json design_json(const Experiment& ex, const DesignSpec& spec, const std::vector<std::vector<double>>& sets,
                           const std::vector<DesignCandidate>& candidates, const DesignRunInfo& run);

/// predicted_se.csv: per candidate and free parameter, the nominal value, the predicted
/// standard error and relative standard error.
std::string predicted_se_csv(const std::vector<DesignCandidate>& candidates);

/// A candidate's input as a CSV: the time column and the input's column (the experiment's
/// names), full precision.
std::string candidate_csv(const Experiment& ex, const DesignSpec& spec, const DesignCandidate& c);

/// The file names a report writes.
std::vector<std::string> design_report_files(const std::vector<DesignCandidate>& candidates);

/// Writes the report into `dir` (prepared by the caller), design.json last.
void write_design_report(const std::filesystem::path& dir, const Experiment& ex, const DesignSpec& spec,
                         const std::vector<std::vector<double>>& sets, const std::vector<DesignCandidate>& candidates,
                         const DesignRunInfo& run);

/// The terminal's table: each candidate's criteria and relative standard errors.
std::string design_summary_text(const DesignSpec& spec, const std::vector<DesignCandidate>& candidates,
                                const std::filesystem::path& dir);

}  // namespace tvid

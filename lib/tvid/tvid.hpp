#pragma once
// tvid's public API: what a program does with the library that `tvid fit` and `tvid
// simulate` do from the shell. Load an experiment file, score a parameter set on its
// windows, identify its free parameters (and write the report directory). Only the
// standard library appears here: the engine's own headers (its SIMD packs, its model
// templates) stay inside the compiled library, so a consumer compiles with its own flags at
// C++20. docs/api.md documents it with an example.
//
//     #include <tvid/tvid.hpp>
//     const tvid::api::Experiment ex = tvid::api::Experiment::load("configs/cvt_tipin.yaml");
//     const tvid::api::FitOutcome fit = tvid::api::fit(ex, {.threads = 2});
//     for (const auto& p : fit.parameters) std::printf("%s = %g ± %g %s\n", p.name.c_str(), ...);

#include <cstdint>
#include <filesystem>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

namespace tvid::api {

/// The library's version, e.g. "0.1.0".
std::string version();

/// Bad input: the experiment file, its recording, an override or a parameter vector. what()
/// is one line, "FILE:LINE: key: what is wrong" where the file and line are known (the
/// `tvid` tool exits 2 on it).
class InputError : public std::runtime_error {
public:
    using std::runtime_error::runtime_error;
};

/// A free parameter of the experiment, as the file sets it.
struct Parameter {
    std::string name;
    std::string unit;       ///< SI, e.g. "N m/rad"
    double init = 0.0;
    double min = 0.0, max = 0.0;  ///< its bounds (±inf where the file gives none)
};

/// How one output fits on one split (estimation or validation), pooled over its windows.
struct OutputScore {
    std::string output;
    std::string unit;
    double rmse = 0.0;
    double fit_percent = 0.0;             ///< 100·(1 − ‖e‖/‖y − ȳ‖)
    double q_index = 0.0;                 ///< the methodology paper's Q index [%]
    double max_abs_residual_ratio = 0.0;  ///< fraction (docs/report-format.md defines it)
};

/// A parameter set scored on every window.
struct Score {
    bool simulated = false;               ///< every window simulated (else the figures are not all finite)
    double cost = 0.0;                    ///< the estimation cost, as the optimizer sees it
    std::vector<OutputScore> estimation;
    std::vector<OutputScore> validation;  ///< empty without validation windows
};

/// An experiment file, read and checked, with its recording. Cheap to copy (shared, immutable).
class Experiment {
public:
    /// Reads `file` (YAML) and its recording. `overrides` as the command line's `--set`:
    /// "KEY.PATH=VALUE", e.g. "estimation.optimizer=lm". Throws InputError on bad input.
    static Experiment load(const std::filesystem::path& file, const std::vector<std::string>& overrides = {});

    const std::string& name() const;
    /// The free parameters, in the order every parameter vector of this API uses.
    std::vector<Parameter> free_parameters() const;
    /// Their init values.
    std::vector<double> initial_values() const;
    /// The measured outputs, in the order of the scores.
    std::vector<std::string> outputs() const;

    struct State;  ///< the library's side (opaque)
    const State& state() const { return *state_; }

private:
    explicit Experiment(std::shared_ptr<const State> state) : state_(std::move(state)) {}
    std::shared_ptr<const State> state_;
};

/// Scores the free parameter values `free` (in free_parameters() order) on every window of
/// the experiment, on up to `threads` threads (0: all cores; the result does not depend on
/// it). Throws InputError when `free` has the wrong length.
Score evaluate(const Experiment& experiment, const std::vector<double>& free, int threads = 0);

struct FitSettings {
    int threads = 0;                      ///< 0: all cores; the result does not depend on it
    std::optional<std::uint64_t> seed;    ///< replaces the experiment's seed (swarm, NLopt, multistart)
    /// Where to write the report directory, as `tvid fit -o DIR` writes it; empty: no report.
    std::filesystem::path report_dir;
    bool force = false;                   ///< replace a report directory tvid wrote before
};

struct FittedParameter {
    std::string name;
    std::string unit;
    double value = 0.0;
    double standard_error = 0.0;          ///< NaN where the data do not determine it
};

struct Finding {
    std::string severity;                 ///< "info", "warning" or "error"
    std::string code;                     ///< e.g. "residuals_not_white" (docs/report-format.md)
    std::string subject;                  ///< the parameter, output or window, or empty
    std::string message;
    std::string advice;
};

struct FitOutcome {
    bool success = false;                 ///< a finite cost was reached
    bool converged = false;               ///< the optimizer met its tolerance (the swarm: its budget ran out)
    std::string optimizer;                ///< "pso", "lm", "nlopt", "pso+lm" or "multistart"
    std::string termination;              ///< why it stopped
    std::vector<FittedParameter> parameters;  ///< the free parameters at the optimum
    Score score;                          ///< the optimum on every window
    std::vector<Finding> verdict;         ///< errors first
    std::filesystem::path report_dir;     ///< where the report went; empty when none was asked
    double seconds = 0.0;                 ///< wall time of the fit
};

/// Identifies the experiment's free parameters with its configured optimizer, judges the
/// optimum as `tvid fit` does, and writes the report directory when settings.report_dir is
/// set. Throws InputError on bad input (every parameter fixed, a report directory that is
/// not tvid's without `force`).
FitOutcome fit(const Experiment& experiment, const FitSettings& settings = {});

}  // namespace tvid::api

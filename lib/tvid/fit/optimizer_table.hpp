#pragma once
// The optimizers of a fit, one row each: how to run it, what it adds to the report, what
// it plans for the progress line. run_fit, the report and `tvid fit` look an optimizer up
// here and nowhere else.
//
// Adding an optimizer: its kind's file and row on the experiment floor (its name, traits
// and settings section: experiment/optimizer_kinds/table.hpp, which the experiment reader
// walks), and a file lib/tvid/fit/optimizers/NAME_run.cpp that defines its run's row
// (`OptimizerEntry NAME_optimizer()`), which this table takes from the same row. Its run
// keeps its own settings as run and its own summary in OptimizerRun::settings and
// ::summary, which its report functions read back.

#include <string>
#include <string_view>
#include <vector>

#include <nlohmann/json.hpp>

#include "tvid/fit/fit_run.hpp"

namespace tvid {

struct OptimizerEntry {
    OptimizerKind kind;
    /// Runs the optimizer on the problem: fills its part of the FitResult (its settings as
    /// run, its own summary, the threads) and returns what every optimizer reports. The
    /// options' progress callback already says stop once a stop is requested.
    OptimizerRun (*run)(const IdentificationProblem& problem, const FitOptions& options, FitResult& result);
    /// Its own keys of summary.json's `optimizer` block: settings as run, phases, starts.
    nlohmann::json (*details)(const Experiment& experiment, const FitResult& result);
    /// The iterations it plans, for the progress line.
    int (*planned_iterations)(const EstimationSettings& settings);
    /// It may stop before its planned iterations (the progress line shows them as a cap).
    bool planned_is_cap = true;
    /// starts.csv, one row per start; null when the optimizer has no starts.
    std::string (*starts_csv)(const IdentificationProblem& problem, const FitResult& result) = nullptr;
    /// How the terminal's summary line names the run ("pso, 512 particles"); null: the
    /// name and the termination ("lm (converged)").
    std::string (*headline)(const FitResult& result) = nullptr;

    const char* name() const { return optimizer_name(kind); }
};

/// Every optimizer, in the order of OptimizerKind.
const std::vector<OptimizerEntry>& optimizer_table();

/// The row of `kind`; throws std::logic_error when the table has none.
const OptimizerEntry& optimizer_entry(OptimizerKind kind);

/// The row named `name` ("pso", "pso+lm", ...), or null.
const OptimizerEntry* find_optimizer(std::string_view name);

}  // namespace tvid

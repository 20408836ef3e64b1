#pragma once
// The optimizer's own part of a report: its settings and phases in summary.json's
// `optimizer` block, and starts.csv (one row per multistart start). Both come from the
// optimizer's row of the optimizer table (fit/optimizer_table.hpp).

#include <string>

#include <nlohmann/json.hpp>

#include "tvid/fit/fit_run.hpp"

namespace tvid {

/// The keys the optimizer that ran adds to summary.json's `optimizer` block (its settings,
/// and for pso+lm the swarm and polish phases, for multistart every start).
nlohmann::json optimizer_details_json(const Experiment& experiment, const FitResult& fit);

/// starts.csv: start, the initial point, the final parameters, initial and final cost,
/// iterations, evaluations, termination; one row per start. Empty unless an optimizer
/// with starts (multistart) ran.
std::string starts_csv(const IdentificationProblem& problem, const FitResult& fit);

}  // namespace tvid

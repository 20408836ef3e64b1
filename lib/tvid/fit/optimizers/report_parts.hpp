#pragma once
// Pieces the optimizers' rows share in their reports: a number for JSON or a CSV cell, and
// the settings blocks of the swarm and of Levenberg–Marquardt.

#include <string>

#include <nlohmann/json.hpp>

#include "tvid/estimation/identification_problem.hpp"
#include "tvid/fit/fit_run.hpp"

namespace tvid::optimizer_report {

/// v, or null when it is not finite (JSON has no inf or NaN).
nlohmann::json number(double v);

/// v with 17 significant digits; "inf", "-inf", or empty for NaN.
std::string csv_cell(double v);

/// Why the swarm's first failed candidate failed: its simulation run again, alone, to the
/// window and account it failed with; empty when no candidate failed (or a stop cut it).
std::string first_failure(const IdentificationProblem& problem, const PsoSummary& swarm);

/// The swarm's settings as run: particles, seed, w, c1, c2.
nlohmann::json swarm_settings(const PsoSettings& settings, const PsoSummary& swarm);

/// How settled the swarm was when it stopped: `spread` {parameter: spread of the personal
/// bests over the box width}, `max_spread`, `recent_improvement`, `window` (PsoConvergence).
nlohmann::json swarm_convergence(const Experiment& experiment, const PsoConvergence& convergence);

/// The experiment's Jacobian kind as the report names it: "sensitivity" or "fd".
const char* jacobian_name(const Experiment& experiment);

/// Levenberg–Marquardt's settings as run: jacobian, ftol, xtol, gtol, max_iterations.
nlohmann::json lm_settings(const Experiment& experiment, const LmSettings& settings);

}  // namespace tvid::optimizer_report

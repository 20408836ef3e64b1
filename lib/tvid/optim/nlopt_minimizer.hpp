#pragma once
// Minimization of a DifferentiableCost with any NLopt algorithm (Johnson, The NLopt
// nonlinear-optimization package) under bounds, with evaluation and time limits.
// Gradient-based algorithms (LD_*, GD_*, and MLSL/AUGLAG with such a local algorithm)
// get the cost's gradient. A failed evaluation is +inf to NLopt and counted. Randomized
// algorithms are seeded (nlopt::srand) before the run, so a seed gives one result. The
// lowest cost seen is kept whatever NLopt returns, and a progress callback returning
// false stops the run (NLopt's force_stop).

#include <functional>
#include <string>
#include <vector>

#include "tvid/optim/differentiable_cost.hpp"
#include "tvid/optim/nlopt_options.hpp"
#include "tvid/optim/optimizer_summary.hpp"
#include "tvid/optim/termination.hpp"

namespace tvid {

/// NLopt's summary: best is the point of the lowest cost seen (best_cost +inf when no
/// evaluation succeeded); evaluations the objective evaluations (with or without gradient),
/// and iterations the same count; failed_evaluations those that returned +inf or NaN;
/// history rows (iteration = evaluation number, 0 for the first) at the first evaluation,
/// at every one that lowers the best cost, and at the last (`evaluations` counts
/// simulations when the cost counts them); termination "cost change below ftol_rel", "step
/// below xtol_rel", "success", "evaluation limit", "time limit", "stopped" (the progress
/// callback), "roundoff limited", "failure", "all evaluations failed"; success: a
/// tolerance was met, or a global algorithm used up its budget (its only stopping rule).
struct NloptSummary : OptimizerSummary {
    std::string algorithm;               ///< NLopt's name, e.g. "LN_BOBYQA"
    std::string local_algorithm;         ///< of MLSL/AUGLAG, or empty
    double initial_cost = 0.0;           ///< the first evaluation's cost
    long long gradient_evaluations = 0;  ///< of the evaluations, those with the gradient
};

/// Called after every evaluation (iteration = evaluation number); return false to stop.
using NloptProgress = std::function<bool(const HistoryRow&)>;

/// Minimize cost(x) subject to lower ≤ x ≤ upper from x0 (projected on the box; global
/// algorithms may ignore it). A bound of ±1e300 or ±inf means none; a global algorithm
/// needs finite bounds. Throws std::invalid_argument for an unknown algorithm, a missing
/// local algorithm, infinite bounds of a global one, or inconsistent sizes.
NloptSummary run_nlopt(const NloptSettings& settings, std::vector<double> x0, const std::vector<double>& lower,
                       const std::vector<double>& upper, DifferentiableCost& cost, const NloptProgress& progress = {});

}  // namespace tvid

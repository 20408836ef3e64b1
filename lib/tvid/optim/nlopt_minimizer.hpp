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
#include "tvid/optim/pso.hpp"  // HistoryRow
#include "tvid/optim/termination.hpp"

namespace tvid {

struct NloptSummary {
    std::string algorithm;               ///< NLopt's name, e.g. "LN_BOBYQA"
    std::string local_algorithm;         ///< of MLSL/AUGLAG, or empty
    std::vector<double> best;            ///< the point of the lowest cost seen
    double best_cost = 0.0;              ///< +inf when no evaluation succeeded
    double initial_cost = 0.0;           ///< the first evaluation's cost
    long long evaluations = 0;           ///< objective evaluations (with or without gradient)
    long long gradient_evaluations = 0;  ///< of which with the gradient
    long long failed_evaluations = 0;    ///< evaluations that returned +inf or NaN
    /// Rows (iteration = evaluation number, 0 for the first) at the first evaluation, at every
    /// one that lowers the best cost, and at the last; `evaluations` counts simulations when
    /// the cost counts them.
    std::vector<HistoryRow> history;
    /// "cost change below ftol_rel", "step below xtol_rel", "success", "evaluation limit",
    /// "time limit", "stopped" (the progress callback), "roundoff limited", "failure",
    /// "all evaluations failed".
    std::string termination;
    TerminationType termination_type = TerminationType::failed;
    /// A tolerance was met, or a global algorithm used up its budget (its only stopping rule).
    bool success = false;
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

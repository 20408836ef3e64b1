#pragma once
// What every optimizer's summary holds (after Ceres' Solver::Summary): the best point and
// its cost, the work done, the history of the best cost, and why it stopped, as a message
// and as a type to decide on. Each optimizer's own summary (LmSummary, PsoSummary,
// NloptSummary, MultistartSummary, HybridSummary) extends it with its own record, and
// the fit's one result builder (fit/optimizers/report_parts.hpp) reads these fields alone.

#include <string>
#include <vector>

#include "tvid/optim/termination.hpp"

namespace tvid {

/// One row of an optimizer's history: after iteration `iteration`, `evaluations` so far and
/// the lowest cost so far.
struct HistoryRow {
    int iteration = 0;
    long long evaluations = 0;
    double best_cost = 0.0;
};

struct OptimizerSummary {
    std::vector<double> best;            ///< the point of the lowest cost seen
    double best_cost = 0.0;              ///< its cost (+inf when no evaluation succeeded)
    int iterations = 0;                  ///< the optimizer's own iterations (NLopt: its evaluations)
    long long evaluations = 0;           ///< simulations, or objective calls when they are not counted
    long long failed_evaluations = 0;    ///< evaluations that failed (+inf, NaN, a failed simulation)
    std::vector<HistoryRow> history;     ///< the lowest cost so far, row by row
    std::string termination;             ///< why it stopped, in words ("cost change below ftol", …)
    TerminationType termination_type = TerminationType::failed;
    /// It ended as it should: a tolerance was met (LM, NLopt, multistart's best start,
    /// pso+lm's polish), or the swarm ran its iterations.
    bool success = false;
};

}  // namespace tvid

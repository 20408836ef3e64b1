#pragma once
// The hybrid `pso+lm`: the particle swarm (pso.hpp) explores the range box, then
// Levenberg–Marquardt (levenberg_marquardt.hpp) polishes its best particle. The swarm
// finds the basin of the global minimum without a good start; LM then converges in a few
// steps to the bottom of that basin, which the swarm approaches only slowly.
//
// Both phases must minimize the same cost: the swarm's candidate cost is Σ r² of the
// least-squares problem (the caller's duty; an experiment's `pso+lm` needs `cost: l2`).
// The history runs on: swarm rows 0 … K, then the LM start at the best particle as row
// K + 1 and LM step k as row K + 1 + k, with cumulative evaluations and the best cost so far.

#include <functional>
#include <string>
#include <vector>

#include "tvid/optim/candidate_evaluator.hpp"
#include "tvid/optim/levenberg_marquardt.hpp"
#include "tvid/optim/pso.hpp"

namespace tvid {

/// The settings of the two phases.
struct HybridSettings {
    PsoSettings pso;
    LmSettings lm;
};

/// pso+lm's summary: best and best_cost (Σ r²) where the polish ended (the swarm's best
/// when it did not run); iterations the swarm updates + LM steps; evaluations the swarm's
/// candidates + LM's simulations (or LM's calls when not counted); termination "swarm:
/// <reason>; lm: <reason>", the swarm's reason when LM did not run, or "stopped" when the
/// progress callback stopped either phase; termination_type the polish's (the swarm's when
/// LM did not run), stopped when either phase was stopped; success: the polish converged.
struct HybridSummary : OptimizerSummary {
    HybridSummary() { termination_type = TerminationType::iteration_limit; }
    PsoSummary pso;                      ///< the swarm phase
    LmSummary lm;                        ///< the polish (empty when it did not run)
    bool polished = false;               ///< LM ran (the swarm found a finite cost and was not stopped)
};

/// Called after every swarm update and LM step with the continued row; false stops.
using HybridProgress = std::function<bool(const HistoryRow&)>;

HybridSummary run_pso_then_lm(const PsoSettings& pso, const LmSettings& lm, const SearchBox& box,
                              CandidateEvaluator& swarm_cost, LeastSquaresProblem& residuals,
                              const HybridProgress& progress = {});

class ParameterScaling;
/// The summary of pso+lm in search coordinates (parameter_scaling.hpp) as parameters: both
/// phases' and its own best point.
void to_parameters(const ParameterScaling& scaling, HybridSummary& summary);

}  // namespace tvid

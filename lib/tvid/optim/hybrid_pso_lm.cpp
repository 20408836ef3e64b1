#include "tvid/optim/hybrid_pso_lm.hpp"

#include "tvid/optim/parameter_scaling.hpp"

#include <algorithm>
#include <cmath>

namespace tvid {

HybridSummary run_pso_then_lm(const PsoSettings& pso, const LmSettings& lm, const SearchBox& box,
                              CandidateEvaluator& swarm_cost, LeastSquaresProblem& residuals,
                              const HybridProgress& progress) {
    HybridSummary s;
    bool stopped = false;
    s.pso = run_pso(pso, box, swarm_cost, [&](const HistoryRow& row) {
        stopped = progress && !progress(row);
        return !stopped;
    });
    s.history = s.pso.history;
    s.best = s.pso.best;
    s.best_cost = s.pso.best_cost;
    s.iterations = s.pso.iterations;
    s.evaluations = s.pso.evaluations;
    s.failed_evaluations = s.pso.failed_evaluations;
    s.termination_type = s.pso.termination_type;
    s.termination = s.pso.termination;
    if (stopped || !std::isfinite(s.pso.best_cost)) return s;

    // The polish from the best particle, its rows continuing the swarm's.
    const int first_row = s.pso.iterations + 1;
    const long long swarm_evaluations = s.pso.evaluations;
    const long long simulations_before = residuals.simulations();
    double best_so_far = s.pso.best_cost;
    auto lm_evaluations = [&](const HistoryRow& row) {
        return simulations_before >= 0 ? residuals.simulations() - simulations_before : row.evaluations;
    };
    s.lm = run_levenberg_marquardt(lm, s.pso.best, box.lower, box.upper, residuals, [&](const HistoryRow& row) {
        best_so_far = std::min(best_so_far, row.best_cost);
        s.history.push_back(HistoryRow{first_row + row.iteration, swarm_evaluations + lm_evaluations(row), best_so_far});
        return !progress || progress(s.history.back());
    });
    s.polished = true;
    const long long lm_calls = s.lm.residual_evaluations + s.lm.jacobian_evaluations;
    s.evaluations = swarm_evaluations + (simulations_before >= 0 ? residuals.simulations() - simulations_before : lm_calls);
    s.failed_evaluations += s.lm.failed_evaluations;
    s.iterations = first_row + s.lm.iterations;
    // A stop (the progress callback) reads the same whichever phase it came in.
    s.termination_type = s.lm.termination_type;
    s.termination = s.lm.termination_type == TerminationType::stopped
                        ? "stopped"
                        : "swarm: " + s.pso.termination + "; lm: " + s.lm.termination;
    s.success = s.lm.success;
    // LM never rises above its start; a start that failed to evaluate keeps the swarm's best.
    if (std::isfinite(s.lm.best_cost) && s.lm.best_cost <= s.pso.best_cost) {
        s.best = s.lm.best;
        s.best_cost = s.lm.best_cost;
    }
    return s;
}

void to_parameters(const ParameterScaling& scaling, HybridSummary& s) {
    to_parameters(scaling, s.pso);
    to_parameters(scaling, s.lm);
    scaling.best_to_parameters(s);
}

}  // namespace tvid

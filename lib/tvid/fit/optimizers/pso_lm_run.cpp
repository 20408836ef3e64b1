// The optimizer table's row of `pso+lm`: the swarm on the l2 cost, then Levenberg–Marquardt
// from its best particle.

#include "tvid/estimation/residual_evaluator.hpp"
#include "tvid/estimation/parallel_evaluator.hpp"
#include "tvid/fit/optimizer_table.hpp"
#include "tvid/fit/optimizers/report_parts.hpp"
#include "tvid/fit/optimizers/search_box.hpp"
#include "tvid/optim/hybrid_pso_lm.hpp"
#include "tvid/parallel/distributed_evaluator.hpp"

namespace tvid {

namespace {

OptimizerRun run_hybrid_fit(const IdentificationProblem& problem, const FitOptions& options, FitResult& r) {
    const EstimationSettings& estimation = problem.experiment().estimation_settings;
    HybridSettings settings{estimation.pso, estimation.lm};
    if (options.seed) settings.pso.seed = *options.seed;
    // The swarm's candidates are scored by every process under mpirun, as for pso alone;
    // the polish runs on the root.
    ParallelEvaluator local(problem, evaluator_options(options));
    DistributedEvaluator swarm_cost(options.processes, local);
    ResidualEvaluator residuals(problem, evaluator_options(options));
    r.threads = local.threads();
    r.processes = swarm_cost.processes();
    const ParameterScaling scaling = search_scaling(problem);
    ScaledCandidateEvaluator swarm_search(swarm_cost, scaling);
    ScaledLeastSquares residuals_search(residuals, scaling);
    HybridSummary h = run_pso_then_lm(settings.pso, settings.lm, search_box(problem), swarm_search,
                                      residuals_search, options.progress);
    to_parameters(scaling, h);
    OptimizerRun run = optimizer_run(
        h, h.evaluations, static_cast<long long>(swarm_cost.right_hand_sides()) + residuals.right_hand_sides());
    run.first_failure = optimizer_report::first_failure(problem, h.pso);
    // The polish's Jacobian, when the polish ended the fit.
    if (h.lm.best == h.best) run.jacobian_at_best = std::move(h.lm.jacobian_at_best);
    run.swarm = h.pso.convergence;
    run.settings = settings;
    run.summary = std::move(h);
    return run;
}

// Both phases minimize the l2 cost; the polish starts at the swarm's best particle.
nlohmann::json hybrid_details(const Experiment& ex, const FitResult& fit) {
    using optimizer_report::number;
    const HybridSettings& settings = *fit.settings_of<HybridSettings>();
    const HybridSummary& h = *fit.summary_of<HybridSummary>();
    nlohmann::json swarm = optimizer_report::swarm_settings(settings.pso, h.pso);
    swarm["iterations"] = h.pso.iterations;
    swarm["evaluations"] = h.pso.evaluations;
    swarm["cost"] = number(h.pso.best_cost);
    swarm["termination"] = h.pso.termination;
    swarm["convergence"] = optimizer_report::swarm_convergence(ex, h.pso.convergence);
    nlohmann::json polish = optimizer_report::lm_settings(ex, settings.lm);
    polish["ran"] = !h.lm.history.empty();
    polish["initial_cost"] = number(h.lm.initial_cost);
    polish["cost"] = number(h.lm.best_cost);
    polish["iterations"] = h.lm.iterations;
    polish["termination"] = h.lm.termination;
    return nlohmann::json{{"swarm", swarm}, {"polish", polish}};
}

// The swarm's updates, its initial evaluation, then the polish's steps.
int hybrid_iterations(const EstimationSettings& settings) {
    return settings.pso.iterations + 1 + settings.lm.max_iterations;
}

}  // namespace

OptimizerEntry pso_lm_optimizer() {
    return OptimizerEntry{.kind = OptimizerKind::pso_lm,
                          .run = run_hybrid_fit,
                          .details = hybrid_details,
                          .planned_iterations = hybrid_iterations};
}

}  // namespace tvid

// The optimizer table's row of `pso`: the particle swarm (Yoshida & Takamatsu) on the configured cost,
// its candidates scored on every thread and, under mpirun, every process.

#include "tvid/estimation/parallel_evaluator.hpp"
#include "tvid/fit/optimizer_table.hpp"
#include "tvid/fit/optimizers/report_parts.hpp"
#include "tvid/fit/optimizers/search_box.hpp"
#include "tvid/parallel/distributed_evaluator.hpp"

namespace tvid {

namespace {

OptimizerRun run_swarm(const IdentificationProblem& problem, const FitOptions& options, FitResult& r) {
    PsoSettings settings = problem.experiment().estimation_settings.pso;
    if (options.seed) settings.seed = *options.seed;
    ParallelEvaluator local(problem, evaluator_options(options));
    DistributedEvaluator evaluator(options.processes, local);
    r.threads = local.threads();
    r.processes = evaluator.processes();
    const ParameterScaling scaling = search_scaling(problem);
    ScaledCandidateEvaluator search(evaluator, scaling);
    PsoSummary swarm = run_pso(settings, search_box(problem), search, options.progress);
    to_parameters(scaling, swarm);
    OptimizerRun run = optimizer_run(swarm, swarm.evaluations, static_cast<long long>(evaluator.right_hand_sides()));
    run.first_failure = optimizer_report::first_failure(problem, swarm);
    run.swarm = swarm.convergence;
    run.settings = settings;
    run.summary = std::move(swarm);
    return run;
}

nlohmann::json swarm_details(const Experiment& ex, const FitResult& fit) {
    const PsoSummary& swarm = *fit.summary_of<PsoSummary>();
    nlohmann::json j = optimizer_report::swarm_settings(*fit.settings_of<PsoSettings>(), swarm);
    j["convergence"] = optimizer_report::swarm_convergence(ex, swarm.convergence);
    return j;
}

int swarm_iterations(const EstimationSettings& settings) { return settings.pso.iterations; }

// The swarm runs its iterations to the end: its size says more than its termination.
std::string swarm_headline(const FitResult& fit) {
    return "pso, " + std::to_string(fit.summary_of<PsoSummary>()->particles) + " particles";
}

}  // namespace

OptimizerEntry pso_optimizer() {
    return OptimizerEntry{.kind = OptimizerKind::pso,
                          .run = run_swarm,
                          .details = swarm_details,
                          .planned_iterations = swarm_iterations,
                          .planned_is_cap = false,
                          .headline = swarm_headline};
}

}  // namespace tvid

#include "tvid/fit/fit_run.hpp"

#include <chrono>
#include <cmath>

#include "tvid/estimation/experiment_least_squares.hpp"
#include "tvid/estimation/parallel_evaluator.hpp"
#include "tvid/parallel/distributed_evaluator.hpp"

namespace tvid {

namespace {

OptimizerRun run_swarm(const IdentificationProblem& problem, const FitOptions& options, FitResult& r) {
    r.pso_settings = problem.experiment().estimation_settings.pso;
    if (options.seed) r.pso_settings.seed = *options.seed;
    ParallelEvaluator local(problem, options.threads);
    DistributedEvaluator evaluator(options.processes, local);
    r.threads = local.threads();
    r.processes = evaluator.processes();
    const SearchBox box{problem.lower(), problem.upper(), problem.range_lower(), problem.range_upper()};
    r.pso = run_pso(r.pso_settings, box, evaluator, options.progress);
    return OptimizerRun{"pso",
                        r.pso.best,
                        r.pso.best_cost,
                        r.pso.iterations,
                        r.pso.evaluations,
                        r.pso.failed_evaluations,
                        r.pso.history,
                        r.pso.termination,
                        r.pso.termination == "iteration limit"};
}

// Seed 000: nonlinear least squares by Levenberg–Marquardt from the experiment's init.
OptimizerRun run_least_squares(const IdentificationProblem& problem, const FitOptions& options, FitResult& r) {
    r.lm_settings = problem.experiment().estimation_settings.lm;
    ExperimentLeastSquares least_squares(problem, options.threads, problem.experiment().estimation_settings.jacobian);
    r.threads = least_squares.threads();
    // The history counts simulations, as for the swarm.
    std::vector<HistoryRow> history;
    const LmProgress progress = [&](const HistoryRow& row) {
        HistoryRow sims = row;
        sims.evaluations = least_squares.simulations();
        history.push_back(sims);
        return options.progress ? options.progress(sims) : true;
    };
    r.lm = run_levenberg_marquardt(r.lm_settings, problem.initial(), problem.lower(), problem.upper(), least_squares,
                                   progress);
    return OptimizerRun{"lm",
                        r.lm.best,
                        r.lm.best_cost,
                        r.lm.iterations,
                        least_squares.simulations(),
                        r.lm.failed_evaluations,
                        history,
                        r.lm.termination,
                        r.lm.success};
}

}  // namespace

FitResult run_fit(const IdentificationProblem& problem, const FitOptions& options) {
    using clock = std::chrono::steady_clock;
    const auto t0 = clock::now();
    FitResult r;
    r.run = problem.experiment().estimation_settings.optimizer == OptimizerKind::lm
                ? run_least_squares(problem, options, r)
                : run_swarm(problem, options, r);
    r.optimizer_seconds = std::chrono::duration<double>(clock::now() - t0).count();

    r.success = std::isfinite(r.run.best_cost);
    r.best_free = r.success ? r.run.best : problem.initial();
    r.best_params = problem.full_parameters(r.best_free);
    r.evaluation = evaluate_parameters(problem, r.best_params);
    if (r.success) r.uncertainty = estimate_uncertainty(problem, r.best_free);
    r.wall_seconds = std::chrono::duration<double>(clock::now() - t0).count();
    return r;
}

}  // namespace tvid

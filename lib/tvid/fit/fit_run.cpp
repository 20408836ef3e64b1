#include "tvid/fit/fit_run.hpp"

#include <chrono>
#include <cmath>

#include "tvid/estimation/parallel_evaluator.hpp"

namespace tvid {

FitResult run_fit(const IdentificationProblem& problem, const FitOptions& options) {
    using clock = std::chrono::steady_clock;
    const auto t0 = clock::now();
    const Experiment& ex = problem.experiment();
    FitResult r;
    r.optimizer = "pso";
    r.pso_settings = ex.estimation_settings.pso;
    if (options.seed) r.pso_settings.seed = *options.seed;

    ParallelEvaluator evaluator(problem, options.threads);
    r.threads = evaluator.threads();
    const SearchBox box{problem.lower(), problem.upper(), problem.range_lower(), problem.range_upper()};
    r.pso = run_pso(r.pso_settings, box, evaluator, options.progress);
    r.optimizer_seconds = std::chrono::duration<double>(clock::now() - t0).count();

    r.success = std::isfinite(r.pso.best_cost);
    r.best_free = r.success ? r.pso.best : problem.initial();
    r.best_params = problem.full_parameters(r.best_free);
    r.evaluation = evaluate_parameters(problem, r.best_params);
    if (r.success) r.uncertainty = estimate_uncertainty(problem, r.best_free);
    r.wall_seconds = std::chrono::duration<double>(clock::now() - t0).count();
    return r;
}

}  // namespace tvid

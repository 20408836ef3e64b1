#include "tvid/fit/fit_run.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>

#include "tvid/estimation/experiment_least_squares.hpp"
#include "tvid/estimation/parallel_evaluator.hpp"
#include "tvid/fit/optimizer_runs.hpp"
#include "tvid/parallel/distributed_evaluator.hpp"

namespace tvid {

namespace {

bool stop_requested(const FitOptions& options) { return options.stop && options.stop->load(std::memory_order_relaxed); }

// The caller's progress callback, and false once a stop is requested.
std::function<bool(const HistoryRow&)> stoppable_progress(const FitOptions& options) {
    return [&options](const HistoryRow& row) {
        const bool go_on = !options.progress || options.progress(row);
        return go_on && !stop_requested(options);
    };
}

OptimizerRun run_swarm(const IdentificationProblem& problem, const FitOptions& options, FitResult& r) {
    r.pso_settings = problem.experiment().estimation_settings.pso;
    if (options.seed) r.pso_settings.seed = *options.seed;
    ParallelEvaluator local(problem, options.threads, options.stop);
    DistributedEvaluator evaluator(options.processes, local);
    r.threads = local.threads();
    r.processes = evaluator.processes();
    const SearchBox box{problem.lower(), problem.upper(), problem.range_lower(), problem.range_upper()};
    r.pso = run_pso(r.pso_settings, box, evaluator, stoppable_progress(options));
    OptimizerRun run{"pso",
                        r.pso.best,
                        r.pso.best_cost,
                        r.pso.iterations,
                        r.pso.evaluations,
                        r.pso.failed_evaluations,
                        r.pso.history,
                        r.pso.termination,
                        r.pso.termination == "iteration limit"};
    run.right_hand_sides = static_cast<long long>(evaluator.right_hand_sides());
    return run;
}

// Seed 000: nonlinear least squares by Levenberg–Marquardt from the experiment's init.
OptimizerRun run_least_squares(const IdentificationProblem& problem, const FitOptions& options, FitResult& r) {
    r.lm_settings = problem.experiment().estimation_settings.lm;
    ExperimentLeastSquares least_squares(problem, options.threads, problem.experiment().estimation_settings.jacobian,
                                         options.stop);
    r.threads = least_squares.threads();
    // The history counts simulations, as for the swarm.
    std::vector<HistoryRow> history;
    const LmProgress progress = [&](const HistoryRow& row) {
        HistoryRow sims = row;
        sims.evaluations = least_squares.simulations();
        history.push_back(sims);
        return (!options.progress || options.progress(sims)) && !stop_requested(options);
    };
    r.lm = run_levenberg_marquardt(r.lm_settings, problem.initial(), problem.lower(), problem.upper(), least_squares,
                                   progress);
    OptimizerRun run{"lm",
                        r.lm.best,
                        r.lm.best_cost,
                        r.lm.iterations,
                        least_squares.simulations(),
                        r.lm.failed_evaluations,
                        history,
                        r.lm.termination,
                        r.lm.success};
    run.right_hand_sides = least_squares.right_hand_sides();
    return run;
}

}  // namespace

FitResult run_fit(const IdentificationProblem& problem, const FitOptions& options) {
    using clock = std::chrono::steady_clock;
    const auto t0 = clock::now();
    FitResult r;
    // Every optimizer sees a progress callback that also says stop once a stop is requested.
    FitOptions stoppable = options;
    stoppable.progress = stoppable_progress(options);
    switch (problem.experiment().estimation_settings.optimizer) {
        case OptimizerKind::pso: r.run = run_swarm(problem, options, r); break;
        case OptimizerKind::lm: r.run = run_least_squares(problem, options, r); break;
        case OptimizerKind::nlopt: r.run = run_nlopt_fit(problem, stoppable, r); break;
        case OptimizerKind::pso_lm: r.run = run_hybrid_fit(problem, stoppable, r); break;
        case OptimizerKind::multistart: r.run = run_multistart_fit(problem, stoppable, r); break;
    }
    r.optimizer_seconds = std::chrono::duration<double>(clock::now() - t0).count();
    r.interrupted = stop_requested(options);
    if (r.interrupted) {
        r.run.termination = "interrupted";
        r.run.converged = false;
    }

    r.success = std::isfinite(r.run.best_cost);
    r.best_free = r.success ? r.run.best : problem.initial();
    r.best_params = problem.full_parameters(r.best_free);
    r.evaluation = evaluate_parameters(problem, r.best_params, resolve_thread_count(options.threads));
    if (r.interrupted) r.uncertainty.problem = "skipped: interrupted";  // the user wants out: no extra Jacobian
    else if (r.success) {
        // A least-squares fit ended on the point it last took the Jacobian at: that one.
        JacobianAtOptimum known;
        if (r.lm.jacobian_at_best.size() > 0 && r.lm.best == r.best_free) {
            known.jacobian = &r.lm.jacobian_at_best;
            known.sum_of_squares = r.lm.best_cost;
        }
        r.uncertainty = estimate_uncertainty(problem, r.best_free, known);
    }
    r.wall_seconds = std::chrono::duration<double>(clock::now() - t0).count();
    return r;
}

int planned_iterations(const EstimationSettings& settings) {
    switch (settings.optimizer) {
        case OptimizerKind::pso: return settings.pso.iterations;
        case OptimizerKind::lm: return settings.lm.max_iterations;
        case OptimizerKind::nlopt: return static_cast<int>(std::min<long long>(settings.nlopt.max_evaluations, 1 << 30));
        case OptimizerKind::pso_lm: return settings.pso.iterations + 1 + settings.lm.max_iterations;
        case OptimizerKind::multistart: {
            const int per_start = settings.multistart.max_iterations.value_or(settings.lm.max_iterations);
            return settings.multistart.starts * per_start;
        }
    }
    return 0;
}

}  // namespace tvid

#include "tvid/fit/fit_run.hpp"

#include <chrono>
#include <cmath>
#include <optional>

#include "tvid/estimation/parallel_evaluator.hpp"
#include "tvid/fit/fit_verdict.hpp"
#include "tvid/fit/optimizer_table.hpp"
#include "tvid/util/stop_request.hpp"

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

// How long the evaluation of an interrupted fit's best point may simulate.
constexpr double kStopGraceSeconds = 2.0;

}  // namespace

FitResult run_fit(const IdentificationProblem& problem, const FitOptions& options) {
    using clock = std::chrono::steady_clock;
    const auto t0 = clock::now();
    FitResult r;
    // Every optimizer sees a progress callback that also says stop once a stop is requested.
    FitOptions stoppable = options;
    stoppable.progress = stoppable_progress(options);
    const OptimizerEntry& optimizer = optimizer_entry(problem.experiment().estimation_settings.optimizer);
    {
        // A stop request (Ctrl-C, SIGTERM) reaches into a running simulation while the
        // optimizer runs; the final evaluation below runs whole.
        const InterruptibleSimulations interruptible(options.stop == &stop_request());
        r.run = optimizer.run(problem, stoppable, r);
    }
    r.run.name = optimizer.name();
    r.optimizer_seconds = std::chrono::duration<double>(clock::now() - t0).count();
    r.interrupted = stop_requested(options);
    if (r.interrupted) {
        r.run.termination = "interrupted";
        r.run.termination_type = TerminationType::interrupted;
        r.run.converged = false;
    }

    r.success = std::isfinite(r.run.best_cost);
    if (!r.success) r.run.converged = false;  // nothing converged: no candidate had a finite cost
    r.best_free = r.success ? r.run.best : problem.initial();
    r.best_params = problem.full_parameters(r.best_free);
    // The evaluation after the fit runs whole (no stop request) on the fit's threads.
    EvaluatorOptions after = evaluator_options(options).with_stop(nullptr);
    {
        // After a stop request the report's evaluation gets a few seconds; a simulation
        // still running then is cut short and its window reported as stopped.
        std::optional<SimulationGracePeriod> grace;
        if (r.interrupted) grace.emplace(kStopGraceSeconds);
        r.evaluation = evaluate_parameters(problem, r.best_params, after.team());
    }
    if (r.interrupted) r.uncertainty.problem = "skipped: interrupted";  // the user wants out: no extra Jacobian
    else if (r.success) {
        // A least-squares fit ended on the point it last took the Jacobian at: that one.
        JacobianAtOptimum known;
        if (r.run.jacobian_at_best.size() > 0) {
            known.jacobian = &r.run.jacobian_at_best;
            known.sum_of_squares = r.run.best_cost;
        }
        if (declares_input_noise(problem.definition())) {
            std::vector<const Window*> windows;
            for (const Window& w : problem.definition().estimation) windows.push_back(&w);
            r.input_noise = input_noise_responses(problem, r.best_params, windows, kInputNoiseDraws, after.team());
            known.input_noise = &r.input_noise;
        }
        r.uncertainty = estimate_uncertainty(problem, r.best_free, known, after);
    }
    judge_fit(problem, r, after.team());
    r.wall_seconds = std::chrono::duration<double>(clock::now() - t0).count();
    return r;
}

OptimizerRun optimizer_run(const OptimizerSummary& summary, long long evaluations, long long right_hand_sides) {
    OptimizerRun run;  // run_fit names it after its row
    run.best = summary.best;
    run.best_cost = summary.best_cost;
    run.iterations = summary.iterations;
    run.evaluations = evaluations;
    run.failed_evaluations = summary.failed_evaluations;
    run.history = summary.history;
    run.termination = summary.termination;
    run.termination_type = summary.termination_type;
    run.converged = summary.success;
    run.right_hand_sides = right_hand_sides;
    return run;
}

int planned_iterations(const EstimationSettings& settings) {
    return optimizer_entry(settings.optimizer).planned_iterations(settings);
}

bool planned_iterations_are_a_cap(const EstimationSettings& settings) {
    return optimizer_entry(settings.optimizer).planned_is_cap;
}

}  // namespace tvid

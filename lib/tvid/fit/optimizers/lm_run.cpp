// The optimizer table's row of `lm`: nonlinear least squares by Levenberg–Marquardt from
// the experiment's init (the methodology paper), on the l2 cost.

#include "tvid/estimation/residual_evaluator.hpp"
#include "tvid/fit/optimizer_table.hpp"
#include "tvid/fit/optimizers/report_parts.hpp"
#include "tvid/fit/optimizers/search_box.hpp"

namespace tvid {

namespace {

OptimizerRun run_least_squares(const IdentificationProblem& problem, const FitOptions& options, FitResult& r) {
    const LmSettings& settings = problem.experiment().estimation_settings.lm;
    ResidualEvaluator least_squares(problem, evaluator_options(options));
    r.threads = least_squares.threads();
    // The history counts simulations, as for the swarm.
    std::vector<HistoryRow> history;
    const LmProgress progress = [&](const HistoryRow& row) {
        HistoryRow sims = row;
        sims.evaluations = least_squares.simulations();
        history.push_back(sims);
        return !options.progress || options.progress(sims);
    };
    const ParameterScaling scaling = search_scaling(problem);
    ScaledLeastSquares search(least_squares, scaling);
    const SearchBox box = search_box(problem);
    LmSummary lm = run_levenberg_marquardt(settings, search_initial(problem), box.lower, box.upper, search, progress);
    to_parameters(scaling, lm);
    OptimizerRun run = optimizer_run(lm, least_squares.simulations(), least_squares.right_hand_sides());
    run.history = std::move(history);  // counted in simulations
    run.jacobian_at_best = std::move(lm.jacobian_at_best);
    run.settings = settings;
    run.summary = std::move(lm);
    return run;
}

nlohmann::json least_squares_details(const Experiment& ex, const FitResult& fit) {
    nlohmann::json d = optimizer_report::lm_settings(ex, *fit.settings_of<LmSettings>());
    d["initial_cost"] = optimizer_report::number(fit.summary_of<LmSummary>()->initial_cost);
    return d;
}

int least_squares_iterations(const EstimationSettings& settings) { return settings.lm.max_iterations; }

}  // namespace

OptimizerEntry lm_optimizer() {
    return OptimizerEntry{.kind = OptimizerKind::lm,
                          .run = run_least_squares,
                          .details = least_squares_details,
                          .planned_iterations = least_squares_iterations};
}

}  // namespace tvid

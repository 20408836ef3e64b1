// The optimizer table's row of `lm`: nonlinear least squares by Levenberg–Marquardt from
// the experiment's init (the methodology paper), on the l2 cost.

#include "tvid/estimation/experiment_least_squares.hpp"
#include "tvid/fit/optimizer_table.hpp"
#include "tvid/fit/optimizers/report_parts.hpp"
#include "tvid/fit/optimizers/search_box.hpp"

namespace tvid {

namespace {

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
        return !options.progress || options.progress(sims);
    };
    const ParameterScaling scaling = search_scaling(problem);
    ScaledLeastSquares search(least_squares, scaling);
    const SearchBox box = search_box(problem);
    r.lm = run_levenberg_marquardt(r.lm_settings, search_initial(problem), box.lower, box.upper, search, progress);
    scaling.to_parameters(r.lm);
    return OptimizerRun{.name = {},  // run_fit names it after its row
                        .best = r.lm.best,
                        .best_cost = r.lm.best_cost,
                        .iterations = r.lm.iterations,
                        .evaluations = least_squares.simulations(),
                        .failed_evaluations = r.lm.failed_evaluations,
                        .first_failure = {},  // the swarm's alone
                        .history = history,
                        .termination = r.lm.termination,
                        .termination_type = r.lm.termination_type,
                        .converged = r.lm.termination_type == TerminationType::converged,
                        .right_hand_sides = least_squares.right_hand_sides()};
}

nlohmann::json least_squares_details(const Experiment& ex, const FitResult& fit) {
    nlohmann::json d = optimizer_report::lm_settings(ex, fit);
    d["initial_cost"] = optimizer_report::number(fit.lm.initial_cost);
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

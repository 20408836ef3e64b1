// The optimizer table's row of `nlopt`: any NLopt algorithm from the experiment's init, on
// the configured cost (l1 or l2).

#include <algorithm>

#include "tvid/estimation/experiment_cost.hpp"
#include "tvid/fit/optimizer_table.hpp"
#include "tvid/fit/optimizers/report_parts.hpp"
#include "tvid/fit/optimizers/search_box.hpp"

namespace tvid {

namespace {

OptimizerRun run_nlopt_fit(const IdentificationProblem& problem, const FitOptions& options, FitResult& r) {
    r.nlopt_settings = problem.experiment().estimation_settings.nlopt;
    if (options.seed) r.nlopt_settings.seed = *options.seed;
    ExperimentCost cost(problem, options.threads);
    r.threads = cost.threads();
    const ParameterScaling scaling = search_scaling(problem);
    ScaledCost search(cost, scaling);
    const SearchBox box = search_box(problem);
    r.nlopt = run_nlopt(r.nlopt_settings, search_initial(problem), box.lower, box.upper, search, options.progress);
    scaling.to_parameters(r.nlopt);
    return OptimizerRun{.name = {},  // run_fit names it after its row
                        .best = r.nlopt.best,
                        .best_cost = r.nlopt.best_cost,
                        .iterations = static_cast<int>(r.nlopt.evaluations),
                        .evaluations = cost.simulations(),
                        .failed_evaluations = r.nlopt.failed_evaluations,
                        .first_failure = {},  // the swarm's alone
                        .history = r.nlopt.history,
                        .termination = r.nlopt.termination,
                        .termination_type = r.nlopt.termination_type,
                        // run_nlopt decides: a tolerance, or a global algorithm's whole budget
                        .converged = r.nlopt.success,
                        .right_hand_sides = cost.right_hand_sides()};
}

nlohmann::json nlopt_details(const Experiment& ex, const FitResult& fit) {
    using nlohmann::json;
    const NloptSettings& ns = fit.nlopt_settings;
    json d{{"algorithm", fit.nlopt.algorithm},
           {"local_algorithm", fit.nlopt.local_algorithm.empty() ? json(nullptr) : json(fit.nlopt.local_algorithm)},
           {"max_evaluations", ns.max_evaluations},
           {"max_seconds", ns.max_seconds},
           {"xtol_rel", ns.xtol_rel},
           {"ftol_rel", ns.ftol_rel},
           {"population", ns.population},
           {"seed", ns.seed},
           {"objective_evaluations", fit.nlopt.evaluations},
           {"gradient_evaluations", fit.nlopt.gradient_evaluations},
           {"initial_cost", optimizer_report::number(fit.nlopt.initial_cost)}};
    if (fit.nlopt.gradient_evaluations > 0) d["jacobian"] = optimizer_report::lm_settings(ex, fit)["jacobian"];
    return d;
}

int nlopt_evaluations(const EstimationSettings& settings) {
    return static_cast<int>(std::min<long long>(settings.nlopt.max_evaluations, 1 << 30));
}

}  // namespace

OptimizerEntry nlopt_optimizer() {
    return OptimizerEntry{.kind = OptimizerKind::nlopt,
                          .run = run_nlopt_fit,
                          .details = nlopt_details,
                          .planned_iterations = nlopt_evaluations};
}

}  // namespace tvid

// The optimizer table's row of `nlopt`: any NLopt algorithm from the experiment's init, on
// the configured cost (l1 or l2).

#include <algorithm>

#include "tvid/estimation/problem_cost.hpp"
#include "tvid/fit/optimizer_table.hpp"
#include "tvid/fit/optimizers/report_parts.hpp"
#include "tvid/fit/optimizers/search_box.hpp"

namespace tvid {

namespace {

OptimizerRun run_nlopt_fit(const IdentificationProblem& problem, const FitOptions& options, FitResult& r) {
    NloptSettings settings = problem.experiment().estimation_settings.nlopt;
    if (options.seed) settings.seed = *options.seed;
    ProblemCost cost(problem, evaluator_options(options));
    r.threads = cost.threads();
    const ParameterScaling scaling = search_scaling(problem);
    ScaledCost search(cost, scaling);
    const SearchBox box = search_box(problem);
    NloptSummary nlopt = run_nlopt(settings, search_initial(problem), box.lower, box.upper, search, options.progress);
    scaling.best_to_parameters(nlopt);  // its summary holds no other point
    // Converged: a tolerance was met, or a global algorithm used its whole budget (run_nlopt decides).
    OptimizerRun run = optimizer_run(nlopt, cost.simulations(), cost.right_hand_sides());
    run.settings = settings;
    run.summary = std::move(nlopt);
    return run;
}

nlohmann::json nlopt_details(const Experiment& ex, const FitResult& fit) {
    using nlohmann::json;
    const NloptSettings& ns = *fit.settings_of<NloptSettings>();
    const NloptSummary& nlopt = *fit.summary_of<NloptSummary>();
    json d{{"algorithm", nlopt.algorithm},
           {"local_algorithm", nlopt.local_algorithm.empty() ? json(nullptr) : json(nlopt.local_algorithm)},
           {"max_evaluations", ns.max_evaluations},
           {"max_seconds", ns.max_seconds},
           {"xtol_rel", ns.xtol_rel},
           {"ftol_rel", ns.ftol_rel},
           {"population", ns.population},
           {"seed", ns.seed},
           {"objective_evaluations", nlopt.evaluations},
           {"gradient_evaluations", nlopt.gradient_evaluations},
           {"initial_cost", optimizer_report::number(nlopt.initial_cost)}};
    if (nlopt.gradient_evaluations > 0) d["jacobian"] = optimizer_report::jacobian_name(ex);
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

// The optimizer table's row of `multistart`: Levenberg–Marquardt from Latin-hypercube
// starts of the range box, in parallel, the best kept; starts.csv lists every start.

#include <cmath>
#include <sstream>

#include "tvid/estimation/residual_evaluator.hpp"
#include "tvid/io/csv_field.hpp"
#include "tvid/estimation/parallel_evaluator.hpp"
#include "tvid/fit/optimizer_table.hpp"
#include "tvid/fit/optimizers/report_parts.hpp"
#include "tvid/fit/optimizers/search_box.hpp"

namespace tvid {

namespace {

// Multistart's settings as run: its own, and those of each start's LM.
struct MultistartRunSettings {
    MultistartSettings multistart;
    LmSettings lm;
};

OptimizerRun run_multistart_fit(const IdentificationProblem& problem, const FitOptions& options, FitResult& r) {
    const EstimationSettings& estimation = problem.experiment().estimation_settings;
    MultistartRunSettings settings{estimation.multistart, estimation.lm};
    if (options.seed) settings.multistart.seed = *options.seed;
    if (settings.multistart.max_iterations) settings.lm.max_iterations = *settings.multistart.max_iterations;
    const EvaluatorOptions evaluators = evaluator_options(options);
    const ParameterScaling scaling = search_scaling(problem);
    // The starts share the fit's team (a batch job's share of the cores), each start's
    // evaluator on its part of it.
    const LeastSquaresFactory make = [&problem, &scaling, &evaluators](const ThreadBudget& share) {
        return std::make_unique<ScaledLeastSquares>(
            std::make_unique<ResidualEvaluator>(problem, evaluators.on_share(share)), scaling);
    };
    MultistartSummary m = run_multistart(settings.multistart, settings.lm, search_box(problem), evaluators.team(),
                                         make, options.progress);
    to_parameters(scaling, m);
    r.threads = m.threads * m.threads_per_start;
    OptimizerRun run = optimizer_run(m, m.evaluations, m.right_hand_sides);
    run.starts = m.starts;
    run.best_start = m.best_start;
    run.settings = settings;
    run.summary = std::move(m);
    return run;
}

nlohmann::json multistart_details(const Experiment& ex, const FitResult& fit) {
    using nlohmann::json;
    using optimizer_report::number;
    const MultistartRunSettings& settings = *fit.settings_of<MultistartRunSettings>();
    const MultistartSummary& ms = *fit.summary_of<MultistartSummary>();
    json starts = json::array();
    for (const StartResult& s : ms.starts)
        starts.push_back(json{{"start", s.start},
                              {"initial_cost", number(s.initial_cost)},
                              {"cost", number(s.best_cost)},
                              {"iterations", s.iterations},
                              {"evaluations", s.evaluations},
                              {"termination", s.termination},
                              {"converged", s.success},
                              {"raced_out", s.termination_type == TerminationType::raced_out},
                              {"draws", s.draws}});
    int draws = 0, run = 0, raced_out = 0;
    for (const StartResult& s : ms.starts) {
        draws += s.draws;
        run += std::isfinite(s.best_cost) ? 1 : 0;
        raced_out += s.termination_type == TerminationType::raced_out ? 1 : 0;
    }
    return json{{"starts", settings.multistart.starts},
                {"starts_run", run},
                {"draws", draws},
                {"max_draws", settings.multistart.max_draws},
                {"seed", settings.multistart.seed},
                {"race", settings.multistart.race},
                {"race_iterations", settings.multistart.race_iterations},
                {"raced_out", raced_out},
                {"best_start", ms.best_start},
                {"parallel_starts", ms.threads},
                {"threads_per_start", ms.threads_per_start},
                {"lm", optimizer_report::lm_settings(ex, settings.lm)},
                {"start_results", starts}};
}

// Every start's LM steps.
int multistart_iterations(const EstimationSettings& settings) {
    const int per_start = settings.multistart.max_iterations.value_or(settings.lm.max_iterations);
    return settings.multistart.starts * per_start;
}

// starts.csv: start, the initial point, the final parameters, initial and final cost,
// iterations, evaluations, termination, whether it is the best, the points drawn.
std::string multistart_starts_csv(const IdentificationProblem& problem, const FitResult& fit) {
    using optimizer_report::csv_cell;
    std::ostringstream out;
    out << "start";
    for (const std::string& n : problem.free_names()) out << ',' << csv_field("initial_" + n);
    for (const std::string& n : problem.free_names()) out << ',' << csv_field("final_" + n);
    out << ",initial_cost,cost,iterations,evaluations,termination,best,draws\n";
    for (const StartResult& s : fit.run.starts) {
        out << s.start;
        for (double v : s.initial) out << ',' << csv_cell(v);
        for (double v : s.best) out << ',' << csv_cell(v);
        out << ',' << csv_cell(s.initial_cost) << ',' << csv_cell(s.best_cost) << ',' << s.iterations << ','
            << s.evaluations << ',' << csv_field(s.termination) << ',' << (s.start == fit.run.best_start ? "true" : "false")
            << ',' << s.draws << '\n';
    }
    return out.str();
}

// The terminal's line: the termination, and how many starts the race stopped
// ("multistart (best of 8 starts: cost change below ftol; 5 raced out)").
std::string multistart_headline(const FitResult& fit) {
    int raced_out = 0;
    for (const StartResult& s : fit.run.starts) raced_out += s.termination_type == TerminationType::raced_out ? 1 : 0;
    return "multistart (" + fit.run.termination + (raced_out > 0 ? "; " + std::to_string(raced_out) + " raced out" : "") +
           ")";
}

}  // namespace

OptimizerEntry multistart_optimizer() {
    return OptimizerEntry{.kind = OptimizerKind::multistart,
                          .run = run_multistart_fit,
                          .details = multistart_details,
                          .planned_iterations = multistart_iterations,
                          .starts_csv = multistart_starts_csv,
                          .headline = multistart_headline};
}

}  // namespace tvid

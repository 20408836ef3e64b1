// The public API (tvid/tvid.hpp) over the engine: each call is what the `tvid` tool does
// for the same job, through the same functions, so the API and the tool give the same numbers.

#include "tvid/tvid.hpp"

#include <utility>

#include "tvid/analysis/evaluation.hpp"
#include "tvid/estimation/identification_problem.hpp"
#include "tvid/experiment/experiment.hpp"
#include "tvid/experiment/overrides.hpp"
#include "tvid/fit/fit_run.hpp"
#include "tvid/model/parameter_units.hpp"
#include "tvid/report/parameter_file.hpp"
#include "tvid/report/report_directory.hpp"
#include "tvid/report/report_writer.hpp"
#include "tvid/util/input_error.hpp"

namespace tvid::api {

// The experiment and its identification problem (which refers to the experiment: built in place).
struct Experiment::State {
    explicit State(tvid::Experiment e) : experiment(std::move(e)), problem(experiment) {}
    tvid::Experiment experiment;
    IdentificationProblem problem;
};

namespace {

// The engine's bad-input error as the API's, with the same one line.
template <class F>
auto translating_input_errors(F&& f) -> decltype(f()) {
    try {
        return f();
    } catch (const tvid::InputError& e) {
        throw InputError(e.what());
    }
}

std::vector<OutputScore> scores(const tvid::Experiment& ex, const SplitEvaluation& split) {
    std::vector<OutputScore> out;
    for (std::size_t o = 0; o < split.pooled.size() && o < ex.outputs.size(); ++o) {
        const FitMetrics& m = split.pooled[o];
        const auto& spec = ex.network.outputs[static_cast<std::size_t>(ex.output_indices[o])];
        out.push_back({ex.outputs[o].model_name, output_unit(ex.network, spec), m.rmse, m.fit_percent, m.q_index,
                       m.max_abs_residual_ratio});
    }
    return out;
}

Score score_of(const tvid::Experiment& ex, const Evaluation& e) {
    Score s;
    s.simulated = e.estimation.ok && e.validation.ok;
    s.cost = e.cost;
    s.estimation = scores(ex, e.estimation);
    if (!ex.validation.empty()) s.validation = scores(ex, e.validation);
    return s;
}

}  // namespace

std::string version() { return TVID_VERSION; }

Experiment Experiment::load(const std::filesystem::path& file, const std::vector<std::string>& overrides) {
    return translating_input_errors(
        [&] { return Experiment(std::make_shared<const State>(load_experiment(file, parse_overrides(overrides)))); });
}

const std::string& Experiment::name() const { return state_->experiment.name; }

std::vector<Parameter> Experiment::free_parameters() const {
    const IdentificationProblem& p = state_->problem;
    const std::vector<std::string> units = parameter_units(state_->experiment.network);
    std::vector<Parameter> out;
    for (std::size_t i = 0; i < p.dimension(); ++i)
        out.push_back({p.free_names()[i], units[p.free_indices()[i]], p.initial()[i], p.lower()[i], p.upper()[i]});
    return out;
}

std::vector<double> Experiment::initial_values() const { return state_->problem.initial(); }

std::vector<std::string> Experiment::outputs() const {
    std::vector<std::string> out;
    for (const auto& o : state_->experiment.outputs) out.push_back(o.model_name);
    return out;
}

Score evaluate(const Experiment& experiment, const std::vector<double>& free, int threads) {
    const IdentificationProblem& p = experiment.state().problem;
    if (free.size() != p.dimension())
        throw InputError("evaluate: " + std::to_string(free.size()) + " values given for " +
                         std::to_string(p.dimension()) + " free parameters");
    return score_of(experiment.state().experiment, evaluate_parameters(p, p.full_parameters(free), threads));
}

FitOutcome fit(const Experiment& experiment, const FitSettings& settings) {
    const tvid::Experiment& ex = experiment.state().experiment;
    const IdentificationProblem& problem = experiment.state().problem;
    if (problem.dimension() == 0)
        throw InputError(ex.file.string() + ": parameters: every parameter is fixed: there is nothing to identify");
    OutputDirectoryLock lock;
    if (!settings.report_dir.empty())
        lock = translating_input_errors(
            [&] { return prepare_report_directory(settings.report_dir, settings.force, ex.name); });

    FitOptions options;
    options.threads = settings.threads;
    options.seed = settings.seed;
    const FitResult result = run_fit(problem, options);
    if (!settings.report_dir.empty())
        write_fit_report(settings.report_dir, problem, result, RunContext{TVID_VERSION, "tvid::api::fit"});

    FitOutcome out;
    out.success = result.success;
    out.converged = result.run.converged;
    out.optimizer = result.run.name;
    out.termination = result.run.termination;
    const std::vector<std::string> units = parameter_units(ex.network);
    for (std::size_t i = 0; i < problem.dimension(); ++i) {
        const double se = result.uncertainty.available && i < result.uncertainty.std_error.size()
                              ? result.uncertainty.std_error[i]
                              : std::numeric_limits<double>::quiet_NaN();
        out.parameters.push_back({problem.free_names()[i], units[problem.free_indices()[i]], result.best_free[i], se});
    }
    out.score = score_of(ex, result.evaluation);
    for (const tvid::Finding& f : result.verdict.findings)
        out.verdict.push_back({to_string(f.severity), f.code, f.subject, f.message, f.advice});
    out.report_dir = settings.report_dir;
    out.seconds = result.wall_seconds;
    return out;
}

}  // namespace tvid::api

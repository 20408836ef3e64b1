#include "tvid/io/csv_field.hpp"
#include "tvid/report/report_writer.hpp"

#include <cmath>
#include <cstdio>
#include <limits>
#include <sstream>

#include "tvid/analysis/fit_metrics.hpp"
#include "tvid/analysis/identifiability.hpp"
#include "tvid/experiment/window_recording.hpp"
#include "tvid/fit/fit_verdict.hpp"
#include "tvid/io/atomic_file.hpp"
#include "tvid/io/output_directory.hpp"
#include "tvid/model/parameter_units.hpp"
#include "tvid/report/modes_report.hpp"
#include "tvid/report/optimizer_report.hpp"
#include "tvid/report/report_directory.hpp"
#include "tvid/report/report_values.hpp"
#include "tvid/report/spectra_report.hpp"
#include "tvid/io/json_text.hpp"

namespace tvid {

namespace {

using nlohmann::json;

json bound(const ParameterSetting& p, bool lower) {
    if (lower) return p.has_min ? json(p.min) : json(nullptr);
    return p.has_max ? json(p.max) : json(nullptr);
}

json metrics_json(const FitMetrics& m) {
    return json{{"samples", m.samples},
                {"cost_l1", json_number(m.mean_abs_error)},
                {"cost_l2", json_number(m.sum_sq_error)},
                {"q_index_percent", json_number(m.q_index)},
                {"e0", json_number(m.e0)},
                {"fit_percent", json_number(m.fit_percent)},
                {"rmse", json_number(m.rmse)},
                {"max_abs_residual_ratio_percent", json_number(100.0 * m.max_abs_residual_ratio)},
                {"residual_ratio_min_abs_y", json_number(m.residual_ratio_min_abs_y)}};
}

// The recordings read, with data.recordings: one entry each, and the files and digests as
// summary.json's `data` and `data_sha256` list them (one recording: its file and digest).
json recordings_json(const Experiment& ex) {
    json out = json::array();
    for (const ExperimentRecording& r : ex.recordings)
        out.push_back(json{{"name", r.name}, {"file", r.file.string()}, {"sha256", r.sha256}, {"samples", r.rows.size()}});
    return out;
}

void add_data_fields(const Experiment& ex, json& summary) {
    if (!lists_recordings(ex)) {
        summary["data"] = ex.data_file.string();
        summary["data_sha256"] = ex.data.content_sha256();
        return;
    }
    json files = json::array(), digests = json::array();
    for (const ExperimentRecording& r : ex.recordings) {
        files.push_back(r.file.string());
        digests.push_back(r.sha256);
    }
    summary["data"] = files;
    summary["data_sha256"] = digests;
    summary["recordings"] = recordings_json(ex);
}

// Index of free parameter for model parameter i, or -1.
int free_position(const IdentificationProblem& problem, std::size_t i) {
    const auto& f = problem.free_indices();
    for (std::size_t j = 0; j < f.size(); ++j)
        if (f[j] == i) return static_cast<int>(j);
    return -1;
}

}  // namespace

json split_json(const Experiment& experiment, const SplitEvaluation& split) {
    json pooled = json::object();
    for (std::size_t k = 0; k < experiment.outputs.size(); ++k)
        pooled[experiment.outputs[k].model_name] = metrics_json(split.pooled[k]);
    json windows = json::array();
    for (const WindowEvaluation& w : split.windows) {
        json outs = json::object();
        for (std::size_t k = 0; k < experiment.outputs.size(); ++k)
            outs[experiment.outputs[k].model_name] = metrics_json(w.metrics[k]);
        json entry{{"window", w.trace.window->label},
                   {"status", to_string(w.trace.status)},
                   {"problem", w.trace.problem},
                   {"outputs", outs}};
        if (lists_recordings(experiment)) entry["recording"] = recording_name(experiment, *w.trace.window);
        windows.push_back(std::move(entry));
    }
    return json{{"pooled", pooled}, {"windows", windows}, {"ok", split.ok}};
}

// One coordinate of an estimated start: the recipe's seed, the fitted correction (the
// parameter) and their sum, the start itself, with the correction's standard error.
json initial_state_json(const IdentificationProblem& problem, const FitResult& fit,
                        const NetworkSpec::StartCoordinate& c, int j) {
    const Experiment& ex = problem.experiment();
    const ProblemDefinition::EstimatedStarts& estimated = problem.definition().estimated;
    const std::size_t n = ex.network.nodes.size();
    const NodeSpec& node = ex.network.nodes[c.state % n];
    const auto parameter = static_cast<std::size_t>(c.parameter);
    const double seed = c.window < estimated.seed.size() ? estimated.seed[c.window][c.state] : 0.0;
    const double correction = fit.best_params[parameter];
    const Window& w = ex.estimation[c.window];
    json entry{{"window", w.label},
               {"node", node.name},
               {"coordinate", c.state < n ? (node.linear ? "position" : "angle") : "speed"},
               {"unit", parameter_units(ex.network)[parameter]},
               {"parameter", ex.parameters[parameter].name},
               {"value", json_number(seed + correction)},
               {"seed", json_number(seed)},
               {"correction", json_number(correction)}};
    if (lists_recordings(ex)) entry["recording"] = recording_name(ex, w);
    const bool known = j >= 0 && fit.uncertainty.available;
    const auto jj = static_cast<std::size_t>(std::max(j, 0));
    entry["std_error"] = known ? json_number(fit.uncertainty.std_error[jj]) : json(nullptr);
    entry["determined"] = known ? json(static_cast<bool>(fit.uncertainty.determined[jj])) : json(nullptr);
    return entry;
}

// How an estimated start was made: its recipe, the coordinates fitted in each estimation
// window (as params.json's initial_states) and, with `validation: estimated`, the samples
// each validation window's own start was fitted on.
namespace {
json estimated_start_json(const IdentificationProblem& problem, const FitResult& fit);
json smoothing_json(const Experiment& ex);
}  // namespace

json parameters_json(const IdentificationProblem& problem, const FitResult& fit) {
    const Experiment& ex = problem.experiment();
    const std::vector<std::string> units = parameter_units(ex.network);
    json params = json::array(), initial_states = json::array();
    for (std::size_t i = 0; i < ex.parameters.size(); ++i) {
        const ParameterSetting& p = ex.parameters[i];
        const int j = free_position(problem, i);
        if (const NetworkSpec::StartCoordinate* c = start_coordinate(ex.network, i)) {
            initial_states.push_back(initial_state_json(problem, fit, *c, j));
            continue;
        }
        json entry{{"name", p.name},        {"unit", units[i]}, {"scale", scale_name(p.scale)},
                   {"value", json_number(fit.best_params[i])}, {"init", p.init},
                   {"min", bound(p, true)}, {"max", bound(p, false)},              {"fixed", p.fixed}};
        if (!p.expr.empty()) {
            // A formula of other parameters: its standard error by the delta method.
            entry["expr"] = p.expr;
            const double se = fit.uncertainty.available
                                  ? formula_std_error(ex.network.parameter_formulas, static_cast<int>(i),
                                                         fit.best_params, problem.free_indices(), fit.uncertainty.covariance)
                                  : std::numeric_limits<double>::quiet_NaN();
            entry["std_error"] = std::isfinite(se) ? json_number(se) : json(nullptr);
            entry["ci95"] = std::isfinite(se) ? json::array({json_number(fit.best_params[i] - 1.96 * se),
                                                             json_number(fit.best_params[i] + 1.96 * se)})
                                              : json(nullptr);
            entry["determined"] = nullptr;
        } else if (j >= 0 && fit.uncertainty.available) {
            const auto jj = static_cast<std::size_t>(j);
            entry["std_error"] = json_number(fit.uncertainty.std_error[jj]);
            if (jj < fit.uncertainty.robust_std_error.size())  // correlated residuals' (Newey–West sandwich)
                entry["robust_std_error"] = json_number(fit.uncertainty.robust_std_error[jj]);
            entry["ci95"] = json::array({json_number(fit.uncertainty.ci_low[jj]), json_number(fit.uncertainty.ci_high[jj])});
            entry["determined"] = static_cast<bool>(fit.uncertainty.determined[jj]);
            entry["interval"] = jj < fit.uncertainty.interval.size() ? fit.uncertainty.interval[jj] : "two-sided";
        } else {
            entry["std_error"] = nullptr;
            entry["ci95"] = nullptr;
            entry["determined"] = j < 0 ? json(nullptr) : json(false);
        }
        params.push_back(entry);
    }
    json correlation{{"parameters", problem.free_names()}, {"matrix", json::array()}};
    for (const auto& row : fit.uncertainty.correlation) {
        json r = json::array();
        for (double c : row) r.push_back(json_number(c));
        correlation["matrix"].push_back(r);
    }
    json covariance{{"parameters", problem.free_names()}, {"matrix", json::array()}};
    for (const auto& row : fit.uncertainty.covariance) {
        json r = json::array();
        for (double c : row) r.push_back(json_number(c));
        covariance["matrix"].push_back(r);
    }
    json out{{"experiment", ex.name}, {"model", ex.network.preset}, {"parameters", params},
             {"correlation", correlation}, {"covariance", covariance}};
    if (ex.estimated_start.on) out["initial_states"] = initial_states;
    return out;
}

// The cost's kind and value, and how it weighs the outputs: each output's residual is
// multiplied by `scale` = weight / spread (normalize: spread) or weight (none).
json cost_json(const Experiment& ex, const Evaluation& ev) {
    json outputs = json::array();
    for (std::size_t k = 0; k < ex.outputs.size() && k < ev.output_scale.size(); ++k)
        outputs.push_back({{"name", ex.outputs[k].model_name},
                           {"unit", output_unit(ex.network, ex.network.outputs[static_cast<std::size_t>(ex.output_indices[k])])},
                           {"weight", ex.outputs[k].weight},
                           {"spread", json_number(ev.output_spread[k])},
                           {"scale", json_number(ev.output_scale[k])}});
    return {{"kind", ex.estimation_settings.cost == CostKind::l1 ? "l1" : "l2"},
            {"value", json_number(ev.cost)},
            {"normalize", ev.normalized ? "spread" : "none"},
            {"outputs", outputs}};
}

json verdict_json(const Verdict& verdict) {
    json findings = json::array();
    for (const Finding& f : verdict.findings)
        findings.push_back({{"code", f.code},
                            {"severity", to_string(f.severity)},
                            {"subject", f.subject.empty() ? json(nullptr) : json(f.subject)},
                            {"message", f.message},
                            {"advice", f.advice}});
    return {{"summary", verdict.summary()},
            {"errors", verdict.count(Severity::error)},
            {"warnings", verdict.count(Severity::warning)},
            {"findings", findings}};
}

namespace {

// Per output: whether the residuals of a split are noise (analysis/residual_whiteness.hpp).
json whiteness_json(const Experiment& ex, const std::vector<ResidualWhiteness>& whiteness) {
    json out = json::object();
    for (std::size_t k = 0; k < ex.outputs.size() && k < whiteness.size(); ++k) {
        const ResidualWhiteness& w = whiteness[k];
        if (w.samples == 0) continue;
        out[ex.outputs[k].model_name] = {{"samples", w.samples},
                                         {"rms", json_number(w.rms)},
                                         {"noise_rms", json_number(w.noise_rms)},
                                         {"systematic_share", json_number(w.systematic_share)},
                                         {"lag1_correlation", json_number(w.lag1_correlation)},
                                         {"ljung_box", json_number(w.ljung_box)},
                                         {"ljung_box_lags", w.lags},
                                         {"ljung_box_p", json_number(w.p_value)},
                                         {"white", residual_is_white(w)}};
        if (w.propagated_noise_rms > 0) {  // judged against the declared input noise carried to it
            out[ex.outputs[k].model_name]["input_noise_rms"] = json_number(w.propagated_noise_rms);
            out[ex.outputs[k].model_name]["input_noise_level"] = json_number(w.propagated_noise_level);
        }
    }
    return out;
}

json correlation_json(const CorrelationTest& t, const char* values) {
    if (!t.available) return nullptr;
    json out{{"samples", t.samples}, {values, json::array()}, {"band", json_number(t.band)},
             {"lags_outside", t.outside}};
    for (double x : t.values) out[values].push_back(json_number(x));
    if (std::string(values) == "ccf") out["variance_factor"] = json_number(t.variance_factor);
    return out;
}

// The residual analysis of a split (analysis/residual_correlation.hpp); null without a
// window to analyse.
json split_correlation_json(const Experiment& ex, const ResidualCorrelation& c) {
    bool any = false;
    json outputs = json::object(), inputs = json::object();
    for (std::size_t k = 0; k < ex.outputs.size() && k < c.autocorrelation.size(); ++k) {
        outputs[ex.outputs[k].model_name] = correlation_json(c.autocorrelation[k], "acf");
        any = any || c.autocorrelation[k].available;
    }
    const std::vector<std::size_t> names = correlated_inputs(ex);
    for (std::size_t q = 0; q < names.size() && q < c.cross_correlation.size(); ++q) {
        json per_output = json::object();
        for (std::size_t k = 0; k < ex.outputs.size() && k < c.cross_correlation[q].size(); ++k)
            per_output[ex.outputs[k].model_name] = correlation_json(c.cross_correlation[q][k], "ccf");
        inputs[ex.inputs[names[q]].model_name] = per_output;
    }
    if (!any) return nullptr;
    return {{"lags", c.lags}, {"outputs", outputs}, {"inputs", inputs}};
}

json residual_analysis_json(const Experiment& ex, const FitResult& fit) {
    return {{"confidence", kCorrelationConfidence},
            {"z", kCorrelationZ},
            {"estimation", split_correlation_json(ex, fit.correlation_estimation)},
            {"validation", split_correlation_json(ex, fit.correlation_validation)}};
}

json criteria_json(const InformationCriteria& c) {
    if (!c.available) return nullptr;
    return {{"samples", c.samples}, {"outputs", c.outputs}, {"parameters", c.parameters},
            {"loss", json_number(c.loss)}, {"fpe", json_number(c.fpe)}, {"aic", json_number(c.aic)},
            {"aicc", json_number(c.aicc)}, {"naic", json_number(c.naic)}, {"bic", json_number(c.bic)}};
}

// With how many window starts of the run took substeps, and how many sdirk3's steps: stiff
// candidates (stable_step.hpp).
json stability_json(const StepStability& s, long long subdivided_starts, long long implicit_starts) {
    if (!s.assessed) return nullptr;
    return {{"integrator", "rk4"}, {"step_s", s.step}, {"substeps", s.substeps}, {"implicit", s.implicit},
            {"margin", json_number(s.margin)}, {"window", s.window}, {"rate_per_s", json_number(s.rate)},
            {"frequency_hz", json_number(s.frequency_hz)}, {"damping_ratio", json_number(s.damping_ratio)},
            {"subdivided_starts", subdivided_starts}, {"implicit_starts", implicit_starts}};
}

}  // namespace

json identifiability_json(const IdentifiabilityReport& report) {
    json parameters = json::array();
    std::vector<std::string> undetermined;
    for (const ParameterIdentifiability& p : report.parameters) {
        parameters.push_back(json{{"name", p.name},
                                  {"std_error", json_number(p.std_error)},
                                  {"relative_std_error", json_number(p.relative_std_error)},
                                  {"judged_std_error", json_number(p.judged_std_error)},
                                  {"judged_against", p.judged_against},
                                  {"flag", to_string(p.flag)}});
        if (p.flag == IdentifiabilityFlag::undetermined) undetermined.push_back(p.name);
    }
    json pairs = json::array();
    for (const CorrelatedPair& c : report.correlated_pairs)
        pairs.push_back(json{{"parameters", {c.first, c.second}}, {"correlation", c.correlation}});
    json directions = json::array();
    for (const ParameterCombination& c : report.null_directions) {
        json vector = json::object(), exponents = json::object();
        for (std::size_t j = 0; j < c.vector.size(); ++j) vector[report.parameters[j].name] = c.vector[j];
        for (std::size_t j = 0; j < c.exponents.size(); ++j)
            if (c.exponents[j] != 0.0) exponents[report.parameters[j].name] = c.exponents[j];
        directions.push_back(json{{"combination", c.text},
                                  {"parameters", c.members},
                                  {"exponents", c.multiplicative ? exponents : json(nullptr)},
                                  {"vector", vector}});
    }
    return json{{"available", report.available},
                {"problem", report.problem},
                {"rank", report.rank},
                {"of", report.of},
                {"free_parameters", report.of},
                {"condition_number", json_number(report.condition_number)},
                {"parameters", parameters},
                {"undetermined", undetermined},
                {"correlated_pairs", pairs},
                {"null_directions", directions},
                {"warning", report.warning()}};
}

// What the standard errors assume (analysis/uncertainty.hpp, docs/report-format.md).
static json standard_errors_json(const Experiment& ex, const ParameterUncertainty& u) {
    json out{{"std_error", u.input_noise ? "white measurement noise per output plus the declared input noise carried "
                                           "through the model (the sandwich with the noise model's covariance)"
                                         : "white residuals of one variance, s^2 (J'J)^-1"},
             {"robust_std_error", u.input_noise ? "Newey-West sandwich, at least std_error" : "Newey-West sandwich"},
             {"robust_lags", u.robust_lags}};
    if (u.input_noise) {
        json carried = json::object();
        for (std::size_t k = 0; k < ex.outputs.size() && k < u.propagated_noise_rms.size(); ++k)
            carried[ex.outputs[k].model_name] = json_number(u.propagated_noise_rms[k]);
        out["input_noise"] = {{"draws", kInputNoiseDraws},
                              {"memory_samples", u.input_noise_lags},
                              {"carried_rms", carried}};
    }
    return out;
}

json fit_summary_json(const IdentificationProblem& problem, const FitResult& fit, const RunContext& context) {
    const Experiment& ex = problem.experiment();
    const json identifiability =
        identifiability_json(assess_identifiability(problem, fit.uncertainty, fit.best_free));
    const double evals_per_s =
        fit.optimizer_seconds > 0 ? static_cast<double>(fit.run.evaluations) / fit.optimizer_seconds : 0.0;
    json optimizer{{"name", fit.run.name},
                   {"iterations", fit.run.iterations},
                   {"evaluations", fit.run.evaluations},
                   {"failed_evaluations", fit.run.failed_evaluations},
                   {"first_failure", fit.run.first_failure.empty() ? json(nullptr) : json(fit.run.first_failure)},
                   {"right_hand_sides", fit.run.right_hand_sides},
                   {"termination", fit.run.termination},
                   {"converged", fit.run.converged}};
    optimizer.update(optimizer_details_json(ex, fit));
    json s{{"tool", "tvid"},
           {"version", context.version},
           {"command", context.command_line},
           {"experiment", ex.name},
           {"status", fit.success ? "ok" : "failed"},
           {"interrupted", fit.interrupted},
           {"config", ex.file.string()},
           {"config_sha256", ex.config_sha256},
           {"model", ex.network.preset},
           {"cost", cost_json(ex, fit.evaluation)},
           {"optimizer", optimizer},
           {"threads", fit.threads},
           {"processes", fit.processes},
           {"wall_time_s", fit.wall_seconds},
           {"optimizer_time_s", fit.optimizer_seconds},
           {"evaluations_per_second", evals_per_s},
           {"estimation", split_json(ex, fit.evaluation.estimation)},
           {"validation", split_json(ex, fit.evaluation.validation)},
           {"identifiability", identifiability},
           {"standard_errors", standard_errors_json(ex, fit.uncertainty)},
           // The result itself, as params.json lists it: `fit --json` is the whole fit in one document.
           {"parameters", parameters_json(problem, fit)["parameters"]},
           {"residuals", {{"estimation", whiteness_json(ex, fit.whiteness_estimation)},
                          {"validation", whiteness_json(ex, fit.whiteness_validation)}}},
           {"residual_analysis", residual_analysis_json(ex, fit)},
           {"residual_spectrum", residual_spectrum_json(ex, fit.evaluation)},
           {"information_criteria", criteria_json(fit.criteria)},
           {"step_stability", stability_json(fit.stability, problem.subdivided_starts(), problem.implicit_starts())},
           {"verdict", verdict_json(fit.verdict)}};
    add_data_fields(ex, s);
    if (!ex.smoothing.empty()) s["smoothing"] = smoothing_json(ex);
    if (ex.estimated_start.on) s["initial_state"] = estimated_start_json(problem, fit);
    // The first estimation window's start as the evaluation at these parameters solved it.
    const std::vector<SolvedStart>& starts = fit.evaluation.estimation_starts;
    const SolvedStart* first = fit.evaluation.params == fit.best_params && !starts.empty() ? &starts[0] : nullptr;
    if (json modes = fit_modes_json(problem, fit.best_params, first); !modes.is_null()) s["modes"] = std::move(modes);
    return s;
}

namespace {
// Each smoothed sign's width and how it was chosen (experiment/smoothing_speeds.hpp).
json smoothing_json(const Experiment& ex) {
    json out = json::array();
    for (const SmoothingChoice& c : ex.smoothing)
        out.push_back({{"element", c.element},
                       {"kind", c.kind},
                       {"smoothing_speed", c.speed},
                       {"unit", c.unit},
                       {"given", c.given},
                       {"basis", c.basis},
                       {"largest_speed", c.largest_speed > 0 ? json(c.largest_speed) : json(nullptr)},
                       {"share_within_3", c.share_within >= 0 ? json(c.share_within) : json(nullptr)}});
    return out;
}

json estimated_start_json(const IdentificationProblem& problem, const FitResult& fit) {
    const Experiment& ex = problem.experiment();
    const char* recipe = initial_state_row(ex.initial_state).name;
    json windows = json::array();
    if (ex.estimated_start.validation) {
        const std::vector<double>& time = problem.inputs().time();
        for (const Window& w : ex.validation) {
            const auto [from, to] = problem.estimated_start_samples(w);
            windows.push_back({{"window", w.label},
                               {"estimated_on", json::array({time[from], time[to]})},
                               {"scored", w.first <= w.start}});
        }
    }
    return json{{"kind", "estimated"},
                {"from", recipe},
                {"estimation", parameters_json(problem, fit)["initial_states"]},
                {"validation", ex.estimated_start.validation ? json("estimated") : json("from")},
                {"validation_windows", windows}};
}
}  // namespace

std::string trace_csv(const Experiment& experiment, const SplitEvaluation& split) {
    std::ostringstream out;
    // Each column's unit in brackets after its name: "Tds_measured [N m]".
    out << "t [s],window";
    for (std::size_t k = 0; k < experiment.outputs.size(); ++k) {
        const std::string& n = experiment.outputs[k].model_name;
        const std::string unit = std::string(" [") +
            output_unit(experiment.network, experiment.network.outputs[static_cast<std::size_t>(experiment.output_indices[k])]) + "]";
        out << ',' << csv_field(n + "_measured" + unit) << ',' << csv_field(n + "_simulated" + unit) << ','
            << csv_field(n + "_residual" + unit) << ',' << csv_field(n + "_residual_ratio [%]");
    }
    // With data.angle, the last column is the cumulative crank angle of each sample, as
    // tvid unwrapped it: cycle boundaries are its multiples of data.cycle_deg.
    const bool with_angle = !experiment.crank_angle.empty();
    if (with_angle) out << ",crank_deg [deg]";
    out << '\n';
    for (const WindowEvaluation& w : split.windows) {
        const WindowTrace& tr = w.trace;
        std::vector<double> floor;  // per output: the residual ratio's floor in this window (fit_metrics.hpp)
        for (const std::vector<double>& y : tr.measured) floor.push_back(residual_ratio_floor(y));
        for (std::size_t i = 0; i < tr.time.size(); ++i) {
            // The time and crank angle of the window's own recording (data.recordings are
            // laid end to end on one clock: window_recording.hpp).
            out << csv_cell(recording_time(experiment, *tr.window, tr.time[i]), "%.9g") << ','
                << csv_field(tr.window->label);
            for (std::size_t k = 0; k < tr.measured.size(); ++k) {
                const double y = tr.measured[k][i], ys = tr.simulated[k][i];
                out << ',' << csv_cell(y) << ',' << csv_cell(ys) << ',' << csv_cell(y - ys) << ','
                    << csv_cell(100.0 * residual_ratio(y, ys, floor[k]));
            }
            if (with_angle)
                out << ',' << csv_cell(recording_angle_deg(experiment, *tr.window,
                                                           experiment.crank_angle[tr.samples[i]] * 180.0 / 3.14159265358979323846),
                                       "%.10g");
            out << '\n';
        }
    }
    return out.str();
}

void write_fit_report(const std::filesystem::path& dir, const IdentificationProblem& problem, const FitResult& fit,
                      const RunContext& context) {
    std::error_code ec;
    std::filesystem::create_directories(dir, ec);
    if (ec) throw std::runtime_error("cannot create report directory " + dir.string() + ": " + ec.message());
    const Experiment& ex = problem.experiment();
    // Every name first: a FIFO or a file the run reads under one of them is refused before
    // anything is written.
    check_output_files(dir, fit_report_files());
    // A summary from an earlier run would vouch for files this run is about to replace.
    remove_output_file(dir, "summary.json");

    write_output_file(dir, "params.json", json_text(parameters_json(problem, fit)) + "\n");

    std::ostringstream csv;
    const std::vector<std::string> units = parameter_units(ex.network);
    csv << "name,value,init,min,max,fixed,std_error,ci95_low,ci95_high,unit\n";
    for (std::size_t i = 0; i < ex.parameters.size(); ++i) {
        const ParameterSetting& p = ex.parameters[i];
        const int j = free_position(problem, i);
        const bool unc = j >= 0 && fit.uncertainty.available;
        const auto jj = static_cast<std::size_t>(std::max(j, 0));
        std::string se = unc ? csv_cell(fit.uncertainty.std_error[jj]) : "";
        std::string low = unc ? csv_cell(fit.uncertainty.ci_low[jj]) : "", high = unc ? csv_cell(fit.uncertainty.ci_high[jj]) : "";
        if (!p.expr.empty() && fit.uncertainty.available) {  // a formula's, by the delta method
            const double e = formula_std_error(ex.network.parameter_formulas, static_cast<int>(i), fit.best_params,
                                                  problem.free_indices(), fit.uncertainty.covariance);
            if (std::isfinite(e)) {
                se = csv_cell(e);
                low = csv_cell(fit.best_params[i] - 1.96 * e);
                high = csv_cell(fit.best_params[i] + 1.96 * e);
            }
        }
        csv << csv_field(p.name) << ',' << csv_cell(fit.best_params[i], "%.17g") << ',' << csv_cell(p.init, "%.17g") << ','
            << (p.has_min ? csv_cell(p.min, "%.17g") : "") << ',' << (p.has_max ? csv_cell(p.max, "%.17g") : "") << ','
            << (p.fixed ? "true" : "false") << ',' << se << ',' << low << ',' << high << ',' << csv_field(units[i]) << '\n';
    }
    write_output_file(dir, "params.csv", csv.str());

    write_output_file(dir, "estimation.csv", trace_csv(ex, fit.evaluation.estimation));
    write_output_file(dir, "validation.csv", trace_csv(ex, fit.evaluation.validation));
    write_output_file(dir, "spectra.csv", spectra_csv(ex, fit.evaluation));
    if (const std::string orders = orders_csv(ex, fit.evaluation); !orders.empty())
        write_output_file(dir, "orders.csv", orders);
    else
        remove_output_file(dir, "orders.csv");  // a replaced engine report's

    std::ostringstream hist;
    hist << "iteration,evaluations,best_cost\n";
    for (const HistoryRow& h : fit.run.history)
        hist << h.iteration << ',' << h.evaluations << ',' << csv_cell(h.best_cost, "%.17g") << '\n';
    write_output_file(dir, "history.csv", hist.str());
    const std::string starts = starts_csv(problem, fit);
    if (!starts.empty()) write_output_file(dir, "starts.csv", starts);
    else remove_output_file(dir, "starts.csv");  // a replaced multistart report's, no longer true

    // summary.json last: its presence marks a complete report.
    write_output_file(dir, "summary.json", json_text(fit_summary_json(problem, fit, context)) + "\n");
}

}  // namespace tvid

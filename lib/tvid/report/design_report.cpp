#include "tvid/report/design_report.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <sstream>

#include "tvid/design/excitation_signals.hpp"
#include "tvid/io/atomic_file.hpp"
#include "tvid/io/csv_field.hpp"
#include "tvid/io/json_text.hpp"
#include "tvid/report/report_values.hpp"
#include "tvid/util/text.hpp"

namespace tvid {

using nlohmann::json;

namespace {

std::string full(double v) { return csv_cell(v, "%.17g"); }

// What ranks a candidate: its criterion at the nominal values, or averaged over the draws.
double ranking_value(const DesignSpec& spec, const DesignCandidate& c) {
    if (!c.prediction.simulated) return std::numeric_limits<double>::infinity();
    return spec.draws > 0 ? c.robust_criterion : c.prediction.criterion(spec.criterion);
}

// The index of the candidate ranked first (lowest; a failed one never).
std::size_t best_candidate(const std::vector<DesignCandidate>& candidates, const DesignSpec& spec) {
    std::size_t best = candidates.size();
    for (std::size_t i = 0; i < candidates.size(); ++i) {
        if (!candidates[i].prediction.simulated) continue;
        if (best == candidates.size() || ranking_value(spec, candidates[i]) < ranking_value(spec, candidates[best]))
            best = i;
    }
    return best;
}

json candidate_json(const DesignSpec& spec, const DesignCandidate& c) {
    const PredictedUncertainty& p = c.prediction;
    double peak = 0.0;
    for (double v : c.value) peak = std::max(peak, std::abs(v - spec.base));
    const double rms = rms_about(c.value, spec.base);
    json parameters = json::array();
    for (std::size_t j = 0; j < p.names.size(); ++j)
        parameters.push_back(json{{"name", p.names[j]},
                                  {"nominal", json_number(p.nominal[j])},
                                  {"se", json_number(p.standard_error[j])},
                                  {"relative_se", json_number(p.relative_se[j])},
                                  {"determined", static_cast<bool>(p.determined[j])}});
    json correlation = json::array();
    for (Eigen::Index i = 0; i < p.correlation.rows(); ++i) {
        json row = json::array();
        for (Eigen::Index j = 0; j < p.correlation.cols(); ++j) row.push_back(json_number(p.correlation(i, j)));
        correlation.push_back(row);
    }
    json search = nullptr;
    if (c.search)
        search = json{{"band_edges_hz", c.search->edges},
                      {"band_power", c.search->band_power},
                      {"flat_multisine_criterion", json_number(c.search->flat_criterion)},
                      {"criterion", json_number(c.search->criterion)},
                      {"evaluations", c.search->evaluations},
                      {"method", "BOBYQA over the bands' log powers from the flat multisine, Schroeder phases"}};
    json draws = nullptr;
    if (spec.draws > 0) {
        json each = json::array();
        for (double v : c.draw_criteria) each.push_back(json_number(v));
        draws = json{{"criterion_per_draw", each}, {"averaged_criterion", json_number(c.robust_criterion)}};
    }
    return json{{"name", c.name},
                {"search", search},
                {"robust", draws},
                {"source", c.source},
                {"file", c.file.empty() ? json(nullptr) : json(c.file)},
                {"samples", c.time.size()},
                {"duration_s", c.time.empty() ? 0.0 : c.time.back() - c.time.front()},
                {"rms", json_number(rms)},
                {"peak", json_number(peak)},
                {"crest_factor", json_number(rms > 0 ? peak / rms : std::nan(""))},
                {"min", c.value.empty() ? json(nullptr) : json(*std::min_element(c.value.begin(), c.value.end()))},
                {"max", c.value.empty() ? json(nullptr) : json(*std::max_element(c.value.begin(), c.value.end()))},
                {"simulated", p.simulated},
                {"problem", p.problem},
                {"criteria",
                 {{"d_optimal", json_number(p.d_optimal)},
                  {"a_optimal", json_number(p.a_optimal)},
                  {"worst_relative_se", json_number(p.worst_relative_se)}}},
                {"parameters", parameters},
                {"correlation", correlation}};
}

}  // namespace

json design_json(const Experiment& ex, const DesignSpec& spec, const std::vector<std::vector<double>>& sets,
                 const std::vector<DesignCandidate>& candidates, const DesignRunInfo& run) {
    const auto named = [&](const std::vector<double>& values) {
        json o = json::object();
        for (std::size_t i = 0; i < ex.parameters.size(); ++i) o[ex.parameters[i].name] = json_number(values[i]);
        return o;
    };
    const json nominal = named(sets.front());
    json drawn = json::array();
    for (std::size_t d = 1; d < sets.size(); ++d) drawn.push_back(named(sets[d]));
    json noise = json::object();
    for (std::size_t k = 0; k < ex.outputs.size(); ++k)
        noise[ex.outputs[k].model_name] = json{{"sigma", spec.noise_given[k]}, {"sigma_si", spec.noise[k]}};
    json held = json::object();
    for (std::size_t k = 0; k < ex.inputs.size(); ++k)
        if (k != spec.input && !ex.inputs[k].by_angle) held[ex.inputs[k].model_name] = spec.levels[k];
    json list = json::array();
    for (const DesignCandidate& c : candidates) list.push_back(candidate_json(spec, c));
    const std::size_t best = best_candidate(candidates, spec);
    return json{
        {"tool", "tvid"},
        {"version", run.version},
        {"command", run.command_line},
        {"experiment", ex.file.string()},
        {"config_sha256", ex.config_sha256},
        {"mode", !candidates.empty() && candidates.front().search ? "design" : "evaluate"},
        {"assumptions",
         {{"prediction",
           "local: the Fisher information J^T S^-1 J of the free parameters from exact forward sensitivities, "
           "linearised at the nominal values; the standard errors are those a least-squares fit of a record with "
           "white output noise of the stated standard deviations would reach (Cramer-Rao bound), if the model is "
           "right and the fit lands at the nominal values"},
          {"nominal_source", run.nominal_source},
          {"nominal", nominal},
          {"robust",
           spec.draws > 0
               ? json{{"draws", spec.draws},
                      {"spread", spec.draw_spread},
                      {"seed", spec.draw_seed},
                      {"rule", "each free parameter times a factor drawn log-uniformly within [1/(1 + spread), "
                               "1 + spread], held within its bounds; candidates ranked by the geometric mean of "
                               "the criterion over the nominal values and the draws"},
                      {"parameter_sets", drawn}}
               : json(nullptr)},
          {"noise", noise},
          {"operating_point", {{"input", ex.inputs[spec.input].model_name}, {"base", spec.base}, {"held", held}}},
          {"initial_state", initial_state_row(ex.initial_state).name}}},
        {"design",
         {{"input", ex.inputs[spec.input].model_name},
          {"column", ex.inputs[spec.input].column},
          {"duration_s", spec.duration},
          {"sample_rate_hz", spec.sample_rate},
          {"band_hz", {spec.band_low, spec.band_high}},
          {"limits", {spec.limit_low, spec.limit_high}},
          {"rms", spec.rms},
          {"base", spec.base},
          {"criterion", to_string(spec.criterion)}}},
        {"candidates", list},
        {"best", best < candidates.size() ? json(candidates[best].name) : json(nullptr)},
        {"threads", run.threads},
        {"wall_time_s", run.wall_seconds}};
}

std::string predicted_se_csv(const std::vector<DesignCandidate>& candidates) {
    std::ostringstream out;
    out << "candidate,parameter,nominal,se,relative_se,determined\n";
    for (const DesignCandidate& c : candidates) {
        const PredictedUncertainty& p = c.prediction;
        for (std::size_t j = 0; j < p.names.size(); ++j)
            out << csv_field(c.name) << ',' << csv_field(p.names[j]) << ',' << full(p.nominal[j]) << ','
                << full(p.standard_error[j]) << ',' << full(p.relative_se[j]) << ','
                << (p.determined[j] ? "true" : "false") << '\n';
    }
    return out.str();
}

std::string candidate_csv(const Experiment& ex, const DesignSpec& spec, const DesignCandidate& c) {
    std::ostringstream out;
    out << csv_field(ex.time_column) << ',' << csv_field(ex.inputs[spec.input].column) << '\n';
    for (std::size_t k = 0; k < c.time.size(); ++k) out << full(c.time[k]) << ',' << full(c.value[k]) << '\n';
    return out.str();
}

std::vector<std::string> design_report_files(const std::vector<DesignCandidate>& candidates) {
    std::vector<std::string> files{"design.json", "predicted_se.csv"};
    for (const DesignCandidate& c : candidates)
        if (!c.file.empty()) files.push_back(c.file);
    return files;
}

void write_design_report(const std::filesystem::path& dir, const Experiment& ex, const DesignSpec& spec,
                         const std::vector<std::vector<double>>& sets, const std::vector<DesignCandidate>& candidates,
                         const DesignRunInfo& run) {
    // An earlier run's design.json would vouch for files this run is about to replace.
    remove_output_file(dir, "design.json");
    write_output_file(dir, "predicted_se.csv", predicted_se_csv(candidates));
    for (const DesignCandidate& c : candidates)
        if (!c.file.empty()) write_output_file(dir, c.file, candidate_csv(ex, spec, c));
    write_output_file(dir, "design.json", json_text(design_json(ex, spec, sets, candidates, run)) + "\n");
}

std::string design_summary_text(const DesignSpec& spec, const std::vector<DesignCandidate>& candidates,
                                const std::filesystem::path& dir) {
    std::ostringstream out;
    const auto percent = [](double v) {
        if (!std::isfinite(v)) return std::string("  not determined");
        char buf[32];
        std::snprintf(buf, sizeof buf, "%16.3g", 100 * v);
        return std::string(buf);
    };
    out << "predicted relative standard errors, % (local, at the nominal values; criterion "
        << to_string(spec.criterion) << ")\n";
    out << "  parameter       ";
    for (const DesignCandidate& c : candidates) {
        char buf[32];
        std::snprintf(buf, sizeof buf, "%16s", c.name.c_str());
        out << buf;
    }
    out << '\n';
    const std::vector<std::string>& names = candidates.front().prediction.names;
    for (std::size_t j = 0; j < names.size(); ++j) {
        char buf[32];
        std::snprintf(buf, sizeof buf, "  %-16s", names[j].c_str());
        out << buf;
        for (const DesignCandidate& c : candidates)
            out << (c.prediction.simulated && j < c.prediction.relative_se.size() ? percent(c.prediction.relative_se[j])
                                                                                   : std::string("      not simulated"));
        out << '\n';
    }
    for (const char* row : {"d_optimal", "a_optimal", "worst_relative_se"}) {
        char buf[32];
        std::snprintf(buf, sizeof buf, "  %-16s", row);
        out << buf;
        for (const DesignCandidate& c : candidates) {
            const PredictedUncertainty& p = c.prediction;
            const double v = std::string(row) == "d_optimal" ? p.d_optimal
                             : std::string(row) == "a_optimal" ? p.a_optimal
                                                               : p.worst_relative_se;
            out << (p.simulated ? percent(v) : std::string("      not simulated"));
        }
        out << '\n';
    }
    if (spec.draws > 0) {
        char buf[32];
        std::snprintf(buf, sizeof buf, "  %-16s", "over the draws");
        out << buf;
        for (const DesignCandidate& c : candidates)
            out << (c.prediction.simulated ? percent(c.robust_criterion) : std::string("      not simulated"));
        out << "   (" << to_string(spec.criterion) << ", geometric mean over the nominal values and " << spec.draws
            << " draws)\n";
    }
    const std::size_t best = best_candidate(candidates, spec);
    if (best < candidates.size())
        out << "best by " << to_string(spec.criterion) << (spec.draws > 0 ? " over the draws" : "") << ": "
            << candidates[best].name << '\n';
    for (const DesignCandidate& c : candidates)
        if (!c.prediction.simulated) out << c.name << ": the simulation failed: " << c.prediction.problem << '\n';
    out << "report: " << dir.string() << '\n';
    return out.str();
}

}  // namespace tvid

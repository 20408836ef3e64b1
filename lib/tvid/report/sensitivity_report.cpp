#include "tvid/io/csv_field.hpp"
#include "tvid/report/sensitivity_report.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <limits>
#include <sstream>
#include <stdexcept>

#include "tvid/experiment/window_recording.hpp"
#include "tvid/io/atomic_file.hpp"
#include "tvid/report/report_values.hpp"
#include "tvid/io/json_text.hpp"

namespace tvid {

namespace {

using nlohmann::json;

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// A CSV cell without "-0" (p·0 with p < 0 is -0).
std::string sensitivity_cell(double v, const char* format = "%.10g") { return csv_cell(v == 0.0 ? 0.0 : v, format); }

// The shortest text that reads back to exactly v (parameter values).
std::string exact(double v) {
    if (!std::isfinite(v)) return sensitivity_cell(v);
    char buf[40];
    const auto end = std::to_chars(buf, buf + sizeof buf, v).ptr;
    return std::string(buf, end);
}

// Sample i of a series; NaN past its end (a window whose simulation stopped early).
double at(const std::vector<double>& series, std::size_t i) { return i < series.size() ? series[i] : kNaN; }

template <class Visit>
void for_each_window(const SensitivityStudy& study, Visit&& visit) {
    for (const WindowSensitivity& w : study.estimation) visit(w, "estimation");
    for (const WindowSensitivity& w : study.validation) visit(w, "validation");
}

}  // namespace

std::size_t SensitivityStudy::samples() const {
    std::size_t n = 0;
    for_each_window(*this, [&](const WindowSensitivity& w, const char*) { n += w.time.size(); });
    return n;
}

SensitivityStudy make_sensitivity_study(const IdentificationProblem& problem, const std::vector<double>& values,
                                        std::vector<WindowSensitivity> estimation,
                                        std::vector<WindowSensitivity> validation) {
    const Experiment& ex = problem.experiment();
    SensitivityStudy study;
    study.experiment = ex.name;
    study.model = ex.network.preset;
    for (const ParameterSetting& p : ex.parameters) study.parameters.push_back(p.name);
    study.values = values;
    study.free = problem.free_indices();
    for (const ChannelBinding& o : ex.outputs) study.outputs.push_back(o.model_name);
    study.estimation = std::move(estimation);
    study.validation = std::move(validation);
    if (lists_recordings(ex))
        for (const ExperimentRecording& r : ex.recordings) study.recordings.push_back(r.name);
    const auto own_clock = [&](WindowSensitivity& w) {
        if (w.window)
            for (double& t : w.time) t = recording_time(ex, *w.window, t);
    };
    for (WindowSensitivity& w : study.estimation) own_clock(w);
    for (WindowSensitivity& w : study.validation) own_clock(w);
    return study;
}

std::vector<OutputRanking> rank_parameters(const SensitivityStudy& study) {
    std::vector<OutputRanking> rankings;
    for (std::size_t k = 0; k < study.outputs.size(); ++k) {
        OutputRanking r;
        r.output = study.outputs[k];
        r.samples = study.samples();
        for (std::size_t j = 0; j < study.free.size(); ++j) {
            // Σ (∂y/∂p_j)² over every scored sample; the scaled sum is p_j² times it.
            double sum_sq = 0.0;
            for_each_window(study, [&](const WindowSensitivity& w, const char*) {
                for (std::size_t i = 0; i < w.time.size(); ++i) {
                    const double d = at(w.dydp[k][j], i);
                    sum_sq += d * d;
                }
            });
            ParameterRank p;
            p.free_index = j;
            p.parameter = study.parameters[study.free[j]];
            p.value = study.values[study.free[j]];
            p.rms_raw = r.samples > 0 ? std::sqrt(sum_sq / static_cast<double>(r.samples)) : 0.0;
            p.rms_scaled = std::abs(p.value) * p.rms_raw;  // RMS of p_j ∂y/∂p_j
            r.ranks.push_back(p);
        }
        // Largest scaled sensitivity first; a NaN (unknown) ranks last.
        std::stable_sort(r.ranks.begin(), r.ranks.end(), [](const ParameterRank& a, const ParameterRank& b) {
            if (std::isnan(b.rms_scaled)) return !std::isnan(a.rms_scaled);
            return a.rms_scaled > b.rms_scaled;
        });
        const double largest = r.ranks.empty() ? 0.0 : r.ranks.front().rms_scaled;
        for (std::size_t n = 0; n < r.ranks.size(); ++n) {
            r.ranks[n].rank = static_cast<int>(n) + 1;
            r.ranks[n].relative = largest > 0 ? r.ranks[n].rms_scaled / largest : kNaN;
        }
        rankings.push_back(std::move(r));
    }
    return rankings;
}

std::string sensitivity_csv(const SensitivityStudy& study) {
    std::ostringstream out;
    out << "window,time,output,y";
    for (std::size_t j : study.free) out << ',' << csv_field("d_" + study.parameters[j]);
    for (std::size_t j : study.free) out << ',' << csv_field("s_" + study.parameters[j]);
    out << '\n';
    for_each_window(study, [&](const WindowSensitivity& w, const char*) {
        for (std::size_t i = 0; i < w.time.size(); ++i) {
            for (std::size_t k = 0; k < study.outputs.size(); ++k) {
                out << csv_field(w.window->label) << ',' << sensitivity_cell(w.time[i]) << ',' << csv_field(study.outputs[k]) << ','
                    << sensitivity_cell(at(w.output[k], i));
                for (std::size_t j = 0; j < study.free.size(); ++j) out << ',' << sensitivity_cell(at(w.dydp[k][j], i));
                for (std::size_t j = 0; j < study.free.size(); ++j)
                    out << ',' << sensitivity_cell(study.values[study.free[j]] * at(w.dydp[k][j], i));
                out << '\n';
            }
        }
    });
    return out.str();
}

std::string ranking_csv(const std::vector<OutputRanking>& rankings) {
    std::ostringstream out;
    out << "output,rank,parameter,value,rms_scaled,relative,rms_raw\n";
    for (const OutputRanking& r : rankings)
        for (const ParameterRank& p : r.ranks)
            out << csv_field(r.output) << ',' << p.rank << ',' << csv_field(p.parameter) << ',' << exact(p.value) << ','
                << sensitivity_cell(p.rms_scaled) << ',' << sensitivity_cell(p.relative) << ',' << sensitivity_cell(p.rms_raw) << '\n';
    return out.str();
}

json sensitivity_json(const SensitivityStudy& study, const std::vector<OutputRanking>& rankings,
                      const SensitivityRunInfo& run) {
    json parameters = json::array();
    for (std::size_t i = 0; i < study.parameters.size(); ++i) {
        const bool is_free = std::find(study.free.begin(), study.free.end(), i) != study.free.end();
        parameters.push_back(json{{"name", study.parameters[i]}, {"value", json_number(study.values[i])}, {"fixed", !is_free}});
    }
    json windows = json::array();
    for_each_window(study, [&](const WindowSensitivity& w, const char* split) {
        json entry{{"window", w.window->label},
                   {"split", split},
                   {"samples", w.time.size()},
                   {"status", to_string(w.status)},
                   {"problem", w.problem}};
        if (!study.recordings.empty()) entry["recording"] = study.recordings[w.window->recording];
        windows.push_back(std::move(entry));
    });
    json ranking = json::object();
    for (const OutputRanking& r : rankings) {
        json ranks = json::array();
        for (const ParameterRank& p : r.ranks)
            ranks.push_back(json{{"rank", p.rank},
                                 {"parameter", p.parameter},
                                 {"value", json_number(p.value)},
                                 {"rms_scaled", json_number(p.rms_scaled)},
                                 {"rms_raw", json_number(p.rms_raw)},
                                 {"relative", json_number(p.relative)}});
        ranking[r.output] = ranks;
    }
    json free_names = json::array();
    for (std::size_t j : study.free) free_names.push_back(study.parameters[j]);
    return json{{"tool", "tvid"},
                {"version", run.version},
                {"command", run.command_line},
                {"experiment", study.experiment},
                {"model", study.model},
                {"parameters", parameters},
                {"free_parameters", free_names},
                {"outputs", study.outputs},
                {"windows", windows},
                {"samples", study.samples()},
                {"ranking", ranking},
                {"threads", run.threads},
                {"wall_time_s", run.wall_seconds}};
}

void write_sensitivity_report(const std::filesystem::path& dir, const SensitivityStudy& study,
                              const std::vector<OutputRanking>& rankings, const SensitivityRunInfo& run) {
    std::error_code ec;
    std::filesystem::create_directories(dir, ec);
    if (ec) throw std::runtime_error("cannot create the sensitivity directory " + dir.string() + ": " + ec.message());
    // An earlier run's sensitivity.json would vouch for files this run is about to replace.
    std::filesystem::remove(dir / "sensitivity.json", ec);
    if (ec) throw std::runtime_error("cannot replace " + (dir / "sensitivity.json").string() + ": " + ec.message());
    write_output_file(dir, "sensitivity.csv", sensitivity_csv(study));
    write_output_file(dir, "ranking.csv", ranking_csv(rankings));
    write_output_file(dir, "sensitivity.json", json_text(sensitivity_json(study, rankings, run)) + "\n");
}

}  // namespace tvid

#include "terminal.hpp"

#include "tvid/io/json_text.hpp"

#include "tvid/analysis/identifiability.hpp"
#include "tvid/fit/optimizer_table.hpp"
#include "tvid/report/spectra_report.hpp"

#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <sstream>

namespace tvid::cli {

std::string json_with_report(nlohmann::json document, const std::filesystem::path& report_dir) {
    document["report"] = report_dir.string();
    return json_text(document);
}


bool is_terminal(int fd) { return ::isatty(fd) == 1; }

bool wants_progress_line(bool quiet, bool json) { return !quiet && !json && is_terminal(1) && is_terminal(2); }

namespace {
// "42 s", "3 min 05 s", "1 h 02 min".
std::string duration_text(double seconds) {
    char buf[32];
    const long s = std::lround(std::max(0.0, seconds));
    if (s < 60) std::snprintf(buf, sizeof buf, "%ld s", s);
    else if (s < 3600) std::snprintf(buf, sizeof buf, "%ld min %02ld s", s / 60, s % 60);
    else std::snprintf(buf, sizeof buf, "%ld h %02ld min", s / 3600, (s % 3600) / 60);
    return buf;
}
}  // namespace

std::string progress_text(const HistoryRow& row, int planned, bool at_most, double elapsed) {
    const double rate = elapsed > 0 ? static_cast<double>(row.evaluations) / elapsed : 0.0;
    char line[256];
    int n = std::snprintf(line, sizeof line, "iteration %d/%d  best cost %.6g  %.0f eval/s  %s elapsed", row.iteration,
                          planned, row.best_cost, rate, duration_text(elapsed).c_str());
    // The remaining time from the mean time per iteration so far.
    if (row.iteration > 0 && planned > row.iteration && n > 0 && static_cast<std::size_t>(n) < sizeof line) {
        const double left = elapsed * (planned - row.iteration) / row.iteration;
        std::snprintf(line + n, sizeof line - static_cast<std::size_t>(n), ", %s%s left", at_most ? "at most " : "",
                      duration_text(left).c_str());
    }
    return line;
}

ProgressLine::ProgressLine(bool enabled, int planned, bool at_most)
    : enabled_(enabled), planned_(planned), at_most_(at_most), start_(std::chrono::steady_clock::now()),
      last_draw_(start_) {}

void ProgressLine::update(const HistoryRow& row) {
    if (!enabled_) return;
    const auto now = std::chrono::steady_clock::now();
    if (drawn_ && now - last_draw_ < std::chrono::milliseconds(200) && row.iteration < planned_) return;
    last_draw_ = now;
    drawn_ = true;
    const double elapsed = std::chrono::duration<double>(now - start_).count();
    // \r back to the start of the line, ESC[K clears what a longer earlier line left.
    std::fprintf(stderr, "\r  %s\033[K", progress_text(row, planned_, at_most_, elapsed).c_str());
    std::fflush(stderr);
}

void ProgressLine::finish() {
    if (enabled_ && drawn_) {
        std::fputs("\r\033[K", stderr);
        std::fflush(stderr);
    }
    drawn_ = false;
}

namespace {
std::string percent(double v) {
    if (!std::isfinite(v)) return "n/a";
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.2f %%", v);
    return buf;
}
}  // namespace

std::string split_lines(const Experiment& ex, const SplitEvaluation& split) {
    // Per output the pooled fit, and under it each window's when there are several: a
    // pooled figure can hide a window the model does not follow.
    std::string out;
    char line[512];
    for (std::size_t k = 0; k < ex.outputs.size() && k < split.pooled.size(); ++k) {
        const FitMetrics& m = split.pooled[k];
        if (m.samples == 0) continue;
        std::snprintf(line, sizeof line, "  %-10s %-6s Q %s  fit %s  RMSE %.4g  max |residual ratio| %s\n",
                      split.split.c_str(), ex.outputs[k].model_name.c_str(), percent(m.q_index).c_str(),
                      percent(m.fit_percent).c_str(), m.rmse, percent(100 * m.max_abs_residual_ratio).c_str());
        out += line;
        if (split.windows.size() < 2) continue;
        for (const WindowEvaluation& w : split.windows) {
            if (k >= w.metrics.size() || w.metrics[k].samples == 0) {
                if (w.trace.status != SimulationStatus::ok)
                    out += "      window " + w.trace.window->label + ": " + to_string(w.trace.status) + "\n";
                continue;
            }
            std::snprintf(line, sizeof line, "      window %-20s Q %s  fit %s  RMSE %.4g\n", w.trace.window->label.c_str(),
                          percent(w.metrics[k].q_index).c_str(), percent(w.metrics[k].fit_percent).c_str(),
                          w.metrics[k].rmse);
            out += line;
        }
    }
    return out;
}

std::string evaluation_summary_text(const std::string& command, const Experiment& ex, const Evaluation& ev) {
    char line[256];
    std::snprintf(line, sizeof line, "tvid %s %s: %zu estimation and %zu validation windows\n  cost (%s%s) %.6g\n",
                  command.c_str(), ex.name.c_str(), ev.estimation.windows.size(), ev.validation.windows.size(),
                  ex.estimation_settings.cost == CostKind::l1 ? "l1" : "l2",
                  ev.normalized ? ", each output's residual over its measured spread" : "", ev.cost);
    return line + split_lines(ex, ev.estimation) + split_lines(ex, ev.validation);
}

// Where the residuals are correlated (or their variance differs between outputs), the
// sandwich's standard errors differ from the table's: said when by more than half. With a
// declared input noise, the noise each output carries.
static std::string standard_error_notes(const IdentificationProblem& problem, const ParameterUncertainty& u) {
    const Experiment& ex = problem.experiment();
    std::string robust, out;
    bool differs = false;
    char buf[96];
    for (std::size_t j = 0; j < u.robust_std_error.size() && j < u.std_error.size(); ++j) {
        const double a = u.std_error[j], b = u.robust_std_error[j];
        if (!(a > 0) || !std::isfinite(b)) continue;
        differs = differs || b > 1.5 * a || b < a / 1.5;
        std::snprintf(buf, sizeof buf, "%s%s %.3g (%.2gx)", robust.empty() ? "" : ", ",
                      ex.parameters[problem.free_indices()[j]].name.c_str(), b, b / a);
        robust += buf;
    }
    if (differs)
        out += "  standard errors with correlated residuals (Newey-West, " + std::to_string(u.robust_lags) + " lags" +
               (u.input_noise ? ", at least the table's" : "") + "): " + robust + "\n";
    if (!u.input_noise) return out;
    std::string carried;
    for (std::size_t k = 0; k < ex.outputs.size() && k < u.propagated_noise_rms.size(); ++k) {
        std::snprintf(buf, sizeof buf, "%s%s %.3g", carried.empty() ? "" : ", ", ex.outputs[k].model_name.c_str(),
                      u.propagated_noise_rms[k]);
        carried += buf;
    }
    return out + "  the standard errors hold the declared input noise, carried to " + carried + " (RMS; its memory " +
           std::to_string(u.input_noise_lags) + " samples)\n";
}

// The parameters' table: value, standard error and relative error (a formula's by the delta
// method), then an estimated start's coordinates with their seeds.
static std::string parameter_table(const IdentificationProblem& problem, const FitResult& fit,
                                   const IdentifiabilityReport& identifiability) {
    const Experiment& ex = problem.experiment();
    std::ostringstream out;
    char line[512];
    out << "  parameter        value            std error    relative\n";
    std::string starts;  // an estimated start's coordinates, after the model's parameters
    for (std::size_t i = 0; i < ex.parameters.size(); ++i) {
        const ParameterSetting& p = ex.parameters[i];
        std::string se = p.fixed ? "fixed" : "", relative;
        if (!p.expr.empty()) {  // a formula of others: its standard error by the delta method
            const double e = fit.uncertainty.available
                                 ? formula_std_error(ex.network.parameter_formulas, static_cast<int>(i),
                                                        fit.best_params, problem.free_indices(), fit.uncertainty.covariance)
                                 : std::numeric_limits<double>::quiet_NaN();
            char buf[64];
            std::snprintf(buf, sizeof buf, "%.3g", e);
            se = std::isfinite(e) ? buf : "";
            relative = "= " + p.expr;
        }
        const NetworkSpec::StartCoordinate* start = start_coordinate(ex.network, i);
        for (std::size_t j = 0; j < problem.free_indices().size() && j < identifiability.parameters.size(); ++j) {
            if (problem.free_indices()[j] != i) continue;
            const ParameterIdentifiability& q = identifiability.parameters[j];
            if (q.flag == IdentifiabilityFlag::undetermined) {
                se = "undetermined";
                continue;
            }
            char buf[128];
            std::snprintf(buf, sizeof buf, "%.3g", q.std_error);
            se = buf;
            if (q.judged_against != "its value" && std::isfinite(q.judged_std_error)) {
                // A delay, offset or phase near 0: its error against its natural scale.
                std::snprintf(buf, sizeof buf, "%.3g %% of %s%s", 100 * q.judged_std_error, q.judged_against.c_str(),
                              q.flag == IdentifiabilityFlag::weak ? "  weak" : "");
                relative = buf;
            } else if (std::isfinite(q.relative_std_error)) {
                std::snprintf(buf, sizeof buf, "%.3g %%%s", 100 * q.relative_std_error,
                              q.flag == IdentifiabilityFlag::weak ? "  weak" : "");
                relative = buf;
            }
            if (j < fit.uncertainty.interval.size() && fit.uncertainty.interval[j] == "one-sided") relative += "  on a bound";
        }
        if (start) {
            // The start itself (the recipe's seed plus the fitted correction); its standard
            // error is the correction's.
            const std::vector<std::vector<double>>& seed = problem.definition().estimated.seed;
            const double from = start->window < seed.size() ? seed[start->window][start->state] : 0.0;
            std::snprintf(line, sizeof line, "  %-22s %-16.8g %-12s (seed %.8g %+.6g)\n", p.name.c_str(),
                          from + fit.best_params[i], se.c_str(), from, fit.best_params[i]);
            starts += line;
            continue;
        }
        std::snprintf(line, sizeof line, "  %-14s %-16.8g %-12s %s", p.name.c_str(), fit.best_params[i], se.c_str(),
                      relative.c_str());
        std::string row = line;
        row.erase(row.find_last_not_of(' ') + 1);
        out << row << '\n';
    }
    if (!starts.empty()) out << "  estimated start        value            std error\n" << starts;
    return out.str();
}

// Strongly correlated parameters (|r| > kStrongCorrelation): summary.json's correlated_pairs.
static std::string correlated_pairs_line(const IdentifiabilityReport& identifiability) {
    if (identifiability.correlated_pairs.empty()) return "";
    char line[512];
    std::vector<CorrelatedPair> pairs = identifiability.correlated_pairs;
    std::stable_sort(pairs.begin(), pairs.end(), [](const CorrelatedPair& a, const CorrelatedPair& b) {
        return std::abs(a.correlation) > std::abs(b.correlation);
    });
    constexpr std::size_t kShownPairs = 8;
    std::snprintf(line, sizeof line, "  correlated parameters (|r| > %.2g):", kStrongCorrelation);
    std::string text = line;
    for (std::size_t i = 0; i < pairs.size() && i < kShownPairs; ++i) {
        std::snprintf(line, sizeof line, "%s %s and %s %+.3f", i ? "," : "", pairs[i].first.c_str(),
                      pairs[i].second.c_str(), pairs[i].correlation);
        text += line;
    }
    if (pairs.size() > kShownPairs) text += ", and " + std::to_string(pairs.size() - kShownPairs) + " more";
    return text + '\n';
}

std::string fit_summary_text(const IdentificationProblem& problem, const FitResult& fit, const std::string& report_dir) {
    const Experiment& ex = problem.experiment();
    std::ostringstream out;
    char line[512];
    const OptimizerEntry* optimizer = find_optimizer(fit.run.name);
    const std::string method = optimizer && optimizer->headline ? optimizer->headline(fit)
                                                                : fit.run.name + " (" + fit.run.termination + ")";
    std::snprintf(line, sizeof line,
                  "tvid fit %s: %s, %d iterations, %lld evaluations (%lld failed), %.2f s on %d thread%s%s\n",
                  ex.name.c_str(), method.c_str(), fit.run.iterations, fit.run.evaluations, fit.run.failed_evaluations,
                  fit.wall_seconds, fit.threads, fit.threads == 1 ? "" : "s",
                  fit.processes > 1 ? (" × " + std::to_string(fit.processes) + " processes").c_str() : "");
    out << line;
    if (!fit.run.first_failure.empty())
        out << "  " << fit.run.failed_evaluations << " evaluation" << (fit.run.failed_evaluations == 1 ? "" : "s")
            << " failed; the first: " << fit.run.first_failure << "\n";
    if (fit.interrupted && fit.success)
        out << "  interrupted: the report holds the best parameters after iteration " << fit.run.iterations
            << " (no uncertainty estimate)\n";
    if (fit.interrupted && !fit.success) {
        out << "  interrupted before a candidate was evaluated: no parameters were identified\n";
    } else if (!fit.success) {
        out << (fit.run.termination_type == TerminationType::start_failed
                    ? "  the simulation at the start failed: no parameters were identified\n"
                                     : "  every candidate failed to simulate: no parameters were identified\n");
    } else {
        std::snprintf(line, sizeof line, "  cost (%s%s) %.6g\n", ex.estimation_settings.cost == CostKind::l1 ? "l1" : "l2",
                      fit.evaluation.normalized ? ", each output's residual over its measured spread" : "",
                      fit.evaluation.cost);
        out << line;
    }
    if (const long long stiff = problem.subdivided_starts(); stiff > 0)
        out << "  " << stiff << " window simulation" << (stiff == 1 ? "" : "s")
            << " of stiff candidates took a smaller step than the experiment's, within RK4's stability limit\n";
    if (const long long implicit = problem.implicit_starts(); implicit > 0)
        out << "  " << implicit << " window simulation" << (implicit == 1 ? "" : "s")
            << " of candidates too stiff for RK4's substeps took sdirk3's implicit steps\n";
    out << split_lines(ex, fit.evaluation.estimation) << split_lines(ex, fit.evaluation.validation);
    // Where the estimation residual's variance lies: its dominant band, or order for an engine.
    // A white residual (the whiteness test passes) has no band to name, and the line says so.
    if (fit.success) {
        const std::vector<ResidualSpectrumSummary> spectra = residual_spectrum_summary(ex, fit.evaluation.estimation);
        for (std::size_t k = 0; k < spectra.size(); ++k) {
            const ResidualWhiteness* w = k < fit.whiteness_estimation.size() ? &fit.whiteness_estimation[k] : nullptr;
            if (const std::string text = residual_spectrum_line(spectra[k], w); !text.empty()) out << "  " << text << '\n';
        }
    }
    const IdentifiabilityReport identifiability =
        assess_identifiability(problem, fit.uncertainty, fit.best_free);
    out << parameter_table(problem, fit, identifiability);
    out << standard_error_notes(problem, fit.uncertainty);
    out << correlated_pairs_line(identifiability);
    if (fit.criteria.available) {
        std::snprintf(line, sizeof line, "  AIC %.6g  BIC %.6g  FPE %.4g  (%zu samples, %d parameters)\n", fit.criteria.aic,
                      fit.criteria.bic, fit.criteria.fpe, fit.criteria.samples, fit.criteria.parameters);
        out << line;
    }
    out << verdict_text(fit.verdict);
    out << "  report: " << report_dir << "\n";
    return out.str();
}

std::string verdict_text(const Verdict& verdict) {
    std::string out = "  verdict: " + verdict.summary() + "\n";
    for (const Finding& f : verdict.findings) {
        out += std::string("    ") + to_string(f.severity) + " " + f.code + ": " + f.message + "\n";
        if (f.severity != Severity::info) out += "      try: " + f.advice + "\n";
    }
    return out;
}

std::string sensitivity_summary_text(const SensitivityStudy& study, const std::vector<OutputRanking>& rankings,
                                     const SensitivityRunInfo& run, const std::string& report_dir) {
    std::ostringstream out;
    char line[512];
    const std::size_t windows = study.estimation.size() + study.validation.size();
    std::snprintf(line, sizeof line,
                  "tvid sensitivity %s: %zu window%s, %zu samples, %zu free parameters, %.2f s on %d thread%s\n",
                  study.experiment.c_str(), windows, windows == 1 ? "" : "s", study.samples(), study.free.size(),
                  run.wall_seconds, run.threads, run.threads == 1 ? "" : "s");
    out << line;
    for (const OutputRanking& r : rankings) {
        // RMS of p·∂y/∂p: the output change (in the output's unit) for a 100 % parameter change.
        out << "  " << r.output << ": RMS of p*dy/dp over the scored samples (output change for a 100 % change of p)\n";
        out << "    rank  parameter       value           rms p*dy/dp   relative\n";
        for (const ParameterRank& p : r.ranks) {
            std::snprintf(line, sizeof line, "    %4d  %-14s  %-14.6g  %-12.4g  %s\n", p.rank, p.parameter.c_str(),
                          p.value, p.rms_scaled, percent(p.relative * 100).c_str());
            out << line;
        }
    }
    out << "  report: " << report_dir << "\n";
    return out.str();
}

}  // namespace tvid::cli

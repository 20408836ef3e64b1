#include "terminal.hpp"

#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <sstream>

namespace tvid::cli {

bool is_terminal(int fd) { return ::isatty(fd) == 1; }

ProgressLine::ProgressLine(bool enabled, int total_iterations)
    : enabled_(enabled), total_(total_iterations), start_(std::chrono::steady_clock::now()), last_draw_(start_) {}

void ProgressLine::update(const HistoryRow& row) {
    if (!enabled_) return;
    const auto now = std::chrono::steady_clock::now();
    if (drawn_ && now - last_draw_ < std::chrono::milliseconds(200) && row.iteration < total_) return;
    last_draw_ = now;
    drawn_ = true;
    const double elapsed = std::chrono::duration<double>(now - start_).count();
    const double rate = elapsed > 0 ? static_cast<double>(row.evaluations) / elapsed : 0.0;
    const double eta = row.iteration > 0 ? elapsed * (total_ - row.iteration) / row.iteration : 0.0;
    std::fprintf(stderr, "\r  iteration %d/%d  best cost %.6g  %.0f sim/s  %.1f s elapsed, %.1f s left   ",
                 row.iteration, total_, row.best_cost, rate, elapsed, eta);
    std::fflush(stderr);
}

void ProgressLine::finish() {
    if (enabled_ && drawn_) std::fprintf(stderr, "\r%100s\r", "");
}

namespace {
std::string percent(double v) {
    if (!std::isfinite(v)) return "n/a";
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.2f %%", v);
    return buf;
}
}  // namespace

std::string fit_summary_text(const IdentificationProblem& problem, const FitResult& fit, const std::string& report_dir) {
    const Experiment& ex = problem.experiment();
    std::ostringstream out;
    char line[512];
    const std::string method =
        fit.run.name == "pso" ? "pso, " + std::to_string(fit.pso.particles) + " particles" : "lm (" + fit.run.termination + ")";
    std::snprintf(line, sizeof line,
                  "tvid fit %s: %s, %d iterations, %lld simulations (%lld failed), %.2f s on %d thread%s%s\n",
                  ex.name.c_str(), method.c_str(), fit.run.iterations, fit.run.evaluations, fit.run.failed_evaluations,
                  fit.wall_seconds, fit.threads, fit.threads == 1 ? "" : "s",
                  fit.processes > 1 ? (" × " + std::to_string(fit.processes) + " processes").c_str() : "");
    out << line;
    if (!fit.success) {
        out << (fit.run.name == "lm" ? "  the simulation at the start failed: no parameters were identified\n"
                                     : "  every candidate failed to simulate: no parameters were identified\n");
    } else {
        std::snprintf(line, sizeof line, "  cost (%s) %.6g\n", ex.estimation_settings.cost == CostKind::l1 ? "l1" : "l2",
                      fit.evaluation.cost);
        out << line;
    }
    auto split_line = [&](const SplitEvaluation& split) {
        for (std::size_t k = 0; k < ex.outputs.size() && k < split.pooled.size(); ++k) {
            const FitMetrics& m = split.pooled[k];
            if (m.samples == 0) continue;
            std::snprintf(line, sizeof line, "  %-10s %-6s Q %s  fit %s  RMSE %.4g  max |residual ratio| %.3g\n",
                          split.split.c_str(), ex.outputs[k].model_name.c_str(), percent(m.q_index).c_str(),
                          percent(m.fit_percent).c_str(), m.rmse, m.max_abs_residual_ratio);
            out << line;
        }
    };
    split_line(fit.evaluation.estimation);
    split_line(fit.evaluation.validation);
    out << "  parameter        value            std error\n";
    for (std::size_t i = 0; i < ex.parameters.size(); ++i) {
        const ParameterSetting& p = ex.parameters[i];
        std::string se = p.fixed ? "fixed" : "";
        for (std::size_t j = 0; j < problem.free_indices().size(); ++j) {
            if (problem.free_indices()[j] != i || !fit.uncertainty.available) continue;
            if (!fit.uncertainty.determined[j]) {
                se = "undetermined";
            } else {
                char buf[32];
                std::snprintf(buf, sizeof buf, "%.3g", fit.uncertainty.std_error[j]);
                se = buf;
            }
        }
        std::snprintf(line, sizeof line, "  %-14s %-16.8g %s\n", p.name.c_str(), fit.best_params[i], se.c_str());
        out << line;
    }
    if (fit.uncertainty.available && fit.uncertainty.rank < static_cast<int>(problem.dimension()))
        out << "  warning: the data determine only " << fit.uncertainty.rank << " of " << problem.dimension()
            << " parameter directions (see identifiability in summary.json)\n";
    out << "  report: " << report_dir << "\n";
    return out.str();
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

#pragma once
// Terminal output: a live progress line when stderr is a terminal, and the summary.

#include <chrono>
#include <string>

#include "tvid/fit/fit_run.hpp"
#include "tvid/report/sensitivity_report.hpp"

namespace tvid::cli {

/// True when stream (1 = stdout, 2 = stderr) is a terminal.
bool is_terminal(int fd);

/// A single status line redrawn in place at most a few times a second.
class ProgressLine {
public:
    ProgressLine(bool enabled, int total_iterations);
    void update(const HistoryRow& row);
    void finish();

private:
    bool enabled_;
    int total_;
    std::chrono::steady_clock::time_point start_, last_draw_;
    bool drawn_ = false;
};

/// The short human summary of a fit: cost, Q, parameters, time, report folder.
std::string fit_summary_text(const IdentificationProblem& problem, const FitResult& fit, const std::string& report_dir);

/// The short human summary of `tvid sensitivity`: per output, the ranking table.
std::string sensitivity_summary_text(const SensitivityStudy& study, const std::vector<OutputRanking>& rankings,
                                     const SensitivityRunInfo& run, const std::string& report_dir);

}  // namespace tvid::cli

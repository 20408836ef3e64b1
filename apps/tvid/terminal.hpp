#pragma once
// Terminal output: a live progress line for a person watching a terminal, and the summary.

#include <chrono>
#include <filesystem>
#include <string>

#include <nlohmann/json.hpp>

#include "tvid/fit/fit_run.hpp"
#include "tvid/report/sensitivity_report.hpp"

namespace tvid::cli {

/// What `--json` prints: the command's document with the directory its report was written
/// to under "report", so that a script finds the files without rebuilding the path.
std::string json_with_report(nlohmann::json document, const std::filesystem::path& report_dir);

/// True when stream (1 = stdout, 2 = stderr) is a terminal.
bool is_terminal(int fd);

/// Whether to draw a live progress line: only for a person at a terminal, i.e. stdout and
/// stderr both terminals (nothing when either is piped or redirected, e.g. `| tee`), and
/// never with --quiet or --json.
bool wants_progress_line(bool quiet, bool json);

/// A single status line on stderr, redrawn in place at most five times a second:
/// iteration/planned, best cost, simulations per second, elapsed and remaining time.
class ProgressLine {
public:
    /// `planned`: the iterations the optimizer may take; `at_most`: it may stop earlier
    /// (a tolerance), so the remaining time is an upper bound.
    ProgressLine(bool enabled, int planned, bool at_most);
    void update(const HistoryRow& row);
    /// Clears the line, so the summary starts on a clean line.
    void finish();

private:
    bool enabled_;
    int planned_;
    bool at_most_;
    std::chrono::steady_clock::time_point start_, last_draw_;
    bool drawn_ = false;
};

/// The progress line's text (without the carriage return).
std::string progress_text(const HistoryRow& row, int planned, bool at_most, double elapsed_seconds);

/// The short human summary of a fit: cost, Q, parameters, time, report folder.
std::string fit_summary_text(const IdentificationProblem& problem, const FitResult& fit, const std::string& report_dir);

/// The metric lines of one split: per output the pooled Q, fit %, RMSE and max residual
/// ratio, and under them each window's when there are several.
std::string split_lines(const Experiment& ex, const SplitEvaluation& split);

/// What `tvid validate` and `tvid simulate` print: the cost and the split lines.
std::string evaluation_summary_text(const std::string& command, const Experiment& ex, const Evaluation& ev);

/// "  verdict: clean", or the count and one line per finding with what to try under it.
std::string verdict_text(const Verdict& verdict);

/// The short human summary of `tvid sensitivity`: per output, the ranking table.
std::string sensitivity_summary_text(const SensitivityStudy& study, const std::vector<OutputRanking>& rankings,
                                     const SensitivityRunInfo& run, const std::string& report_dir);

}  // namespace tvid::cli

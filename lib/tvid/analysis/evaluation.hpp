#pragma once
// A parameter vector judged on the experiment: every estimation and validation window
// simulated, with fit metrics per window and output and pooled per split.

#include <string>
#include <vector>

#include "tvid/analysis/fit_metrics.hpp"
#include "tvid/estimation/identification_problem.hpp"

namespace tvid {

struct WindowEvaluation {
    WindowTrace trace;
    std::vector<FitMetrics> metrics;  ///< per output
};

struct SplitEvaluation {
    std::string split;                    ///< "estimation" or "validation"
    std::vector<WindowEvaluation> windows;
    std::vector<FitMetrics> pooled;       ///< per output, over all windows of the split
    bool ok = true;                       ///< every window simulated
};

struct Evaluation {
    std::vector<double> params;           ///< full model parameter vector
    double cost = 0.0;                    ///< the estimation cost (as the optimizer saw it)
    SplitEvaluation estimation;
    SplitEvaluation validation;
    std::vector<double> output_offsets;   ///< per compared output
    /// How the cost weighs each output (ProblemDefinition::output_scale, output_spread, normalized).
    std::vector<double> output_scale, output_spread;
    bool normalized = false;
    /// Each estimation window's start as its trace solved it (empty where it failed): the
    /// analyses at these parameters (step stability, modes) set out from it.
    std::vector<SolvedStart> estimation_starts;
};

/// Simulates every window on up to `threads` threads (one window per thread at a time);
/// the result is the same for any thread count.
Evaluation evaluate_parameters(const IdentificationProblem& problem, const std::vector<double>& params,
                               int threads = 1);

/// Where and why the evaluation is incomplete: "estimation window W: step budget exceeded"
/// for the first window whose simulation failed (diverged, not finite, ...); empty when
/// every window simulated.
std::string first_failed_window(const Evaluation& ev);

/// The number of windows (estimation and validation) whose simulation failed.
int failed_window_count(const Evaluation& ev);

}  // namespace tvid

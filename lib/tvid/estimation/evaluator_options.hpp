#pragma once
// How the evaluators of an identification problem run (ResidualEvaluator, ParallelEvaluator,
// ProblemCost): on how many threads, with what share of a batch's cores, with which kind of
// Jacobian, and under which stop request. A fit builds one from its options
// (fit/fit_run.hpp's evaluator_options) and hands the same one to its optimizer's
// evaluators, to the uncertainty after it and to the input noise's draws, so that a batch
// job's share of the cores and a stop reach all of them alike.

#include <algorithm>
#include <atomic>
#include <optional>

#include "tvid/experiment/experiment.hpp"
#include "tvid/util/thread_budget.hpp"

namespace tvid {

/// The number of threads `threads` means (<= 0: all hardware threads).
int resolve_thread_count(int threads);

struct EvaluatorOptions {
    /// On `threads` threads (<= 0: all hardware threads), the problem's Jacobian kind, no
    /// stop request, no budget; the with_… calls set the rest.
    explicit EvaluatorOptions(int threads_ = 0) : threads(threads_) {}
    EvaluatorOptions& with_jacobian(JacobianKind kind) { jacobian = kind; return *this; }
    EvaluatorOptions& with_stop(const std::atomic<bool>* flag) { stop = flag; return *this; }
    EvaluatorOptions& with_budget(const ThreadBudget* share) { budget = share; return *this; }

    int threads = 0;                          ///< <= 0: all hardware threads
    /// The Jacobian's columns: by forward sensitivities or by differences; unset: the
    /// experiment's (`estimation.lm.jacobian`).
    std::optional<JacobianKind> jacobian;
    /// Give up evaluations once set (may be null): an evaluation in flight ends at its
    /// simulations' next sample.
    const std::atomic<bool>* stop = nullptr;
    /// A batch job's share of the batch's cores (may be null): each parallel region takes
    /// the budget's current team, and `threads` is ignored.
    const ThreadBudget* budget = nullptr;

    /// The threads of the next parallel region.
    int team() const { return budget ? budget->team() : resolve_thread_count(threads); }
    /// The most threads a parallel region may take (a workspace each).
    int most_threads() const { return budget ? budget->cores() : resolve_thread_count(threads); }
    /// The same options on `share` instead of the fit's own threads or budget (multistart's
    /// starts, which split the fit's team).
    EvaluatorOptions on_share(const ThreadBudget& share) const {
        EvaluatorOptions o = *this;
        o.budget = &share;
        return o;
    }
};

}  // namespace tvid

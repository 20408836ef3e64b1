#pragma once
// One identification run: optimizer on the estimation windows, then the optimum judged
// on every window and its uncertainty estimated. What `tvid fit` does between reading
// the experiment and writing the report.

#include <Eigen/Core>
#include <any>
#include <atomic>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "tvid/analysis/evaluation.hpp"
#include "tvid/analysis/information_criteria.hpp"
#include "tvid/analysis/residual_correlation.hpp"
#include "tvid/util/thread_budget.hpp"
#include "tvid/analysis/residual_whiteness.hpp"
#include "tvid/analysis/step_stability.hpp"
#include "tvid/analysis/verdict.hpp"
#include "tvid/estimation/identification_problem.hpp"
#include "tvid/analysis/uncertainty.hpp"
#include "tvid/optim/levenberg_marquardt.hpp"
#include "tvid/optim/multistart.hpp"
#include "tvid/estimation/evaluator_options.hpp"
#include "tvid/optim/nlopt_minimizer.hpp"
#include "tvid/optim/pso.hpp"

namespace tvid {

class ProcessGroup;

struct FitOptions {
    int threads = 0;                        ///< <= 0: all cores
    std::optional<std::uint64_t> seed;      ///< overrides the experiment's seed (swarm, NLopt, multistart)
    std::function<bool(const HistoryRow&)> progress;  ///< called after every iteration; false stops
    /// Stop request (e.g. &stop_request() for Ctrl-C), may be null: once set, the optimizer
    /// stops within about one simulation per thread with the best fully evaluated point,
    /// and the result is marked interrupted.
    const std::atomic<bool>* stop = nullptr;
    /// mpirun: swarm candidates are scored by every process of the group (run_fit on the
    /// root, serve_candidate_evaluations on the others). Levenberg–Marquardt runs on the root alone.
    ProcessGroup* processes = nullptr;
    /// A batch job's share of the batch's cores (util/thread_budget.hpp), or null: then
    /// `threads`. Least squares and the evaluation after the fit take their team from it.
    const ThreadBudget* budget = nullptr;
};

/// The options of every evaluator of the fit (its optimizer's, the uncertainty's, the input
/// noise's draws), from the fit's: the same threads, share of a batch's cores, stop request
/// and the experiment's Jacobian kind for all of them.
inline EvaluatorOptions evaluator_options(const FitOptions& options) {
    return EvaluatorOptions(options.threads).with_stop(options.stop).with_budget(options.budget);
}

/// What every optimizer reports, whichever ran.
struct OptimizerRun {
    std::string name;                       ///< "pso", "lm", "nlopt", "pso+lm" or "multistart"
    std::vector<double> best;               ///< free parameters
    double best_cost = 0.0;                 ///< the estimation cost (l1 or l2 as configured)
    int iterations = 0;
    long long evaluations = 0;              ///< simulations run
    long long failed_evaluations = 0;       ///< candidates whose simulation failed
    /// Why the swarm's first failed candidate failed (the first window its simulation could
    /// not finish, and that simulation's account); empty when none failed.
    std::string first_failure;
    std::vector<HistoryRow> history;        ///< iteration, simulations so far, best cost
    /// Why it stopped, as summary.json and the terminal say it (e.g. "cost change below
    /// ftol", "interrupted"), and as a type to decide on.
    std::string termination;
    TerminationType termination_type = TerminationType::failed;
    /// Decided by each optimizer from its termination type. lm, multistart (its best start),
    /// pso+lm (its polish): an LM tolerance was met; pso: the iteration budget ran out;
    /// nlopt: a tolerance was met, or a global algorithm used its budget
    bool converged = false;
    /// Right-hand sides of the model the optimizer's simulations evaluated, over every
    /// thread and process: the work done (the swarm's stop at each particle's personal best
    /// and a least-squares fit's reuse of simulations lower it).
    long long right_hand_sides = 0;
    /// A least-squares optimizer's Jacobian at `best` (the ResidualEvaluator's, in the
    /// parameters' own units; the uncertainty takes it instead of forming it again); empty
    /// when the optimizer has none there.
    Eigen::MatrixXd jacobian_at_best;
    /// An optimizer that runs from several starts: each start, and the best one (1-based;
    /// 0 when every start failed). Empty for the others.
    std::vector<StartResult> starts;
    int best_start = 0;
    /// An optimizer that runs the swarm: how settled the swarm was when it stopped (the
    /// verdict warns when it was still spread or still improving). Empty for the others.
    std::optional<PsoConvergence> swarm;
    /// The optimizer's own record, of the types its row chooses: its settings as run (seed
    /// resolved) and its own summary (PsoSummary, LmSummary, NloptSummary, HybridSummary,
    /// MultistartSummary, …). Read them with FitResult::summary_of / settings_of.
    std::any settings;
    std::any summary;
};

/// The one result builder: what every optimizer reports, from its summary in the parameters'
/// own coordinates (best, cost, iterations, failed evaluations, history, termination;
/// converged is the summary's success), with the simulations and right-hand sides as its row
/// counts them. The row adds its own parts (first failure, Jacobian at the best, starts,
/// swarm) and its settings and summary.
OptimizerRun optimizer_run(const OptimizerSummary& summary, long long evaluations, long long right_hand_sides);

struct FitResult {
    OptimizerRun run;                       ///< what the optimizer that ran reports, its own record included
    bool success = false;                   ///< a finite cost was reached
    bool interrupted = false;               ///< stopped by FitOptions::stop: best so far, no uncertainty
    std::vector<double> best_free;
    std::vector<double> best_params;        ///< full model parameter vector
    Evaluation evaluation;
    ParameterUncertainty uncertainty;
    /// The declared input noise carried to the estimation windows at the optimum
    /// (analysis/input_noise.hpp), for the uncertainty and the verdict; empty without.
    InputNoiseResponses input_noise;
    /// Per output: whether the residuals are noise, in the estimation and validation windows.
    std::vector<ResidualWhiteness> whiteness_estimation, whiteness_validation;
    /// Per split: the residuals' autocorrelation and their cross-correlation with each input
    /// read by time (fit/fit_verdict.hpp, correlated_inputs), with 99 % bands.
    ResidualCorrelation correlation_estimation, correlation_validation;
    InformationCriteria criteria;           ///< over the estimation windows
    StepStability stability;                ///< of an rk4 simulation at the optimum
    Verdict verdict;                        ///< what the figures above say (fit/fit_verdict.hpp)
    double optimizer_seconds = 0.0;
    double wall_seconds = 0.0;
    int threads = 1;
    int processes = 1;                      ///< processes that scored candidates (threads each)

    /// The optimizer's own summary as type S, or null when the optimizer that ran keeps another.
    template <class S>
    const S* summary_of() const { return std::any_cast<S>(&run.summary); }
    /// Its settings as run, as type S, or null.
    template <class S>
    const S* settings_of() const { return std::any_cast<S>(&run.settings); }
};

FitResult run_fit(const IdentificationProblem& problem, const FitOptions& options);

/// The iterations the configured optimizer plans (for a progress line): swarm updates, LM
/// steps (over every start of multistart), NLopt evaluations.
int planned_iterations(const EstimationSettings& settings);

/// True when the configured optimizer may stop before its planned iterations (every one but
/// the swarm): the progress line then shows them as a cap.
bool planned_iterations_are_a_cap(const EstimationSettings& settings);

}  // namespace tvid

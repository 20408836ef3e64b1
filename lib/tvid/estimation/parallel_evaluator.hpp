#pragma once
// Scores batches of candidates of an IdentificationProblem on all cores. Each thread
// owns a workspace built once; every candidate's cost is computed from its own inputs
// only, so costs are identical for any thread count. Where the problem allows it
// (fixed-step RK4, batch_cost.hpp) the candidates go in groups of kBatchLanes through one
// simulation in SIMD lanes, each lane costing exactly what its candidate costs alone, and
// the groups are formed anew from the surviving candidates as the windows go on. Given a
// stop flag, a batch stops within one simulation (or one piece of a window, in groups) per
// thread once the flag is set (see stopped()).

#include <atomic>
#include <memory>
#include <vector>

#include "tvid/estimation/batch_cost.hpp"
#include "tvid/estimation/evaluator_options.hpp"
#include "tvid/estimation/identification_problem.hpp"
#include "tvid/optim/candidate_evaluator.hpp"

namespace tvid {

class ParallelEvaluator : public CandidateEvaluator {
public:
    /// On options.team() threads (all hardware threads by default, a batch job's share of
    /// the cores under its budget); options.stop (may be null): skip the rest of a batch once set.
    explicit ParallelEvaluator(const IdentificationProblem& problem, const EvaluatorOptions& options = EvaluatorOptions());

    void evaluate(const double* candidates, std::size_t count, std::size_t dimension, double* costs) override;
    /// Each candidate's simulation stops once its partial cost reaches its bound
    /// (IdentificationProblem::cost with a bound).
    void evaluate_bounded(const double* candidates, std::size_t count, std::size_t dimension, const double* bounds,
                          double* costs) override;
    bool stopped() const override { return stopped_; }

    int threads() const { return threads_; }
    /// Whether candidates are simulated in SIMD groups (the default where the problem allows).
    bool batching() const { return batching_; }
    /// Turns the SIMD groups off (one candidate at a time), e.g. to compare; the costs are the same.
    void set_batching(bool on) { batching_ = on && !batch_workspaces_.empty(); }
    /// Right-hand sides evaluated so far, summed over the threads' workspaces.
    std::size_t right_hand_sides() const override;
    /// Of the right-hand sides the SIMD groups' lanes evaluated so far, the share that a
    /// candidate needed (the rest: lanes whose candidate was done while its group went on,
    /// and the empty lanes of the last group); 0 before any group ran.
    double lanes_used() const;

private:
    const IdentificationProblem* problem_;
    int threads_;
    const std::atomic<bool>* stop_;
    bool stopped_ = false;
    std::vector<std::unique_ptr<ProblemWorkspace>> workspaces_;
    std::vector<std::unique_ptr<BatchWorkspace>> batch_workspaces_;  ///< empty when the problem cannot batch
    std::vector<BatchWorkspace*> batch_lanes_;                       ///< the same, as batch_costs takes them
    bool batching_ = false;
};


/// The most threads a run may ask for (the command line refuses more; the library clamps):
/// far beyond any machine's cores, and below what the OpenMP runtime can start.
inline constexpr int kMaxThreads = 1024;

}  // namespace tvid

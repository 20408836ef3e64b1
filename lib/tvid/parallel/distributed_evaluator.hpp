#pragma once
// Swarm candidates scored by every process of a group (`tvid fit` under mpirun). The root
// runs the optimizer; for each batch it broadcasts the candidates, every process scores a
// contiguous slice of them with its own threads (process_slice), and the costs are
// gathered back in candidate order. A cost is computed from its candidate alone, so the
// costs, and the whole swarm, are bit-identical to a single process's.

#include <cstddef>

#include "tvid/optim/candidate_evaluator.hpp"
#include "tvid/parallel/process_group.hpp"

namespace tvid {

/// The root's evaluator. With no group, or a group of one, it is `local` itself.
class DistributedEvaluator : public CandidateEvaluator {
public:
    DistributedEvaluator(ProcessGroup* group, CandidateEvaluator& local);

    void evaluate(const double* candidates, std::size_t count, std::size_t dimension, double* costs) override;
    /// Each process scores its slice with the stop at each candidate's bound (the
    /// particles' personal bests), as `local` alone would.
    void evaluate_bounded(const double* candidates, std::size_t count, std::size_t dimension, const double* bounds,
                          double* costs) override;

    /// The root's own slice was cut short by a stop request (Ctrl-C).
    bool stopped() const override { return local_->stopped(); }

    /// Processes scoring the candidates.
    int processes() const { return group_ ? group_->size() : 1; }

    /// Over every process: the root's own and those the others reported with their costs.
    std::size_t right_hand_sides() const override { return local_->right_hand_sides() + remote_right_hand_sides_; }

private:
    ProcessGroup* group_;
    CandidateEvaluator* local_;
    std::size_t remote_right_hand_sides_ = 0;
};

/// The other processes: score their slice of every batch the root's DistributedEvaluator
/// broadcasts, until the root releases them (CandidateServers).
void serve_candidate_evaluations(ProcessGroup& group, CandidateEvaluator& local, std::size_t dimension);

/// On the root: the other processes serve candidate evaluations while this object lives
/// (whichever optimizer runs, and also when the fit throws); release() or the destructor
/// ends serve_candidate_evaluations on them.
class CandidateServers {
public:
    explicit CandidateServers(ProcessGroup& group) : group_(&group) {}
    ~CandidateServers();
    CandidateServers(const CandidateServers&) = delete;
    CandidateServers& operator=(const CandidateServers&) = delete;
    void release();

private:
    ProcessGroup* group_;
    bool released_ = false;
};

}  // namespace tvid

#include "tvid/parallel/distributed_evaluator.hpp"

#include <algorithm>
#include <cstddef>
#include <exception>
#include <vector>

namespace tvid {

namespace {

// A broadcast batch: a header value saying whether bounds follow, the candidates, then
// (bounded) one bound per candidate. An empty batch releases the servers.
constexpr double kPlainBatch = 0.0;
constexpr double kBoundedBatch = 1.0;

std::vector<double> pack_batch(const double* candidates, std::size_t count, std::size_t dimension,
                               const double* bounds) {
    std::vector<double> batch;
    batch.reserve(1 + count * dimension + (bounds ? count : 0));
    batch.push_back(bounds ? kBoundedBatch : kPlainBatch);
    batch.insert(batch.end(), candidates, candidates + count * dimension);
    if (bounds) batch.insert(batch.end(), bounds, bounds + count);
    return batch;
}

// Scores this process's slice of the broadcast batch, with the stop at each candidate's
// bound when the batch carries bounds (as the root's own ParallelEvaluator would). The
// slice's costs are followed by the right-hand sides their simulations took.
std::vector<double> score_slice(ProcessGroup& group, CandidateEvaluator& local, const std::vector<double>& batch,
                                std::size_t dimension) {
    const bool bounded = batch.front() == kBoundedBatch;
    const std::size_t count = (batch.size() - 1) / (dimension + (bounded ? 1 : 0));
    const double* candidates = batch.data() + 1;
    const ProcessSlice slice = process_slice(count, group.rank(), group.size());
    std::vector<double> costs(slice.size() + 1, 0.0);
    if (slice.size() == 0) return costs;
    const std::size_t rhs_before = local.right_hand_sides();
    const double* mine = candidates + slice.begin * dimension;
    if (bounded)
        local.evaluate_bounded(mine, slice.size(), dimension, candidates + count * dimension + slice.begin,
                               costs.data());
    else
        local.evaluate(mine, slice.size(), dimension, costs.data());
    costs.back() = static_cast<double>(local.right_hand_sides() - rhs_before);
    return costs;
}

}  // namespace

DistributedEvaluator::DistributedEvaluator(ProcessGroup* group, CandidateEvaluator& local)
    : group_(group && group->size() > 1 ? group : nullptr), local_(&local) {}

void DistributedEvaluator::evaluate(const double* candidates, std::size_t count, std::size_t dimension, double* costs) {
    evaluate_bounded(candidates, count, dimension, nullptr, costs);
}

void DistributedEvaluator::evaluate_bounded(const double* candidates, std::size_t count, std::size_t dimension,
                                            const double* bounds, double* costs) {
    if (count == 0) return;
    if (!group_) {
        if (bounds) local_->evaluate_bounded(candidates, count, dimension, bounds, costs);
        else local_->evaluate(candidates, count, dimension, costs);
        return;
    }
    std::vector<double> batch = pack_batch(candidates, count, dimension, bounds);
    group_->broadcast(batch);
    std::vector<double> mine;
    std::exception_ptr failure;
    try {
        mine = score_slice(*group_, *local_, batch, dimension);
    } catch (...) {
        failure = std::current_exception();  // still take part in the gather the others wait in
        mine.assign(process_slice(count, 0, group_->size()).size() + 1, 0.0);
    }
    const std::vector<double> all = group_->gather(mine);
    if (failure) std::rethrow_exception(failure);
    // Rank by rank: its slice's costs, then its right-hand sides.
    std::size_t at = 0;
    for (int rank = 0; rank < group_->size(); ++rank) {
        const std::size_t n = process_slice(count, rank, group_->size()).size();
        std::copy_n(all.begin() + static_cast<std::ptrdiff_t>(at), n, costs);
        costs += n;
        if (rank != 0) remote_right_hand_sides_ += static_cast<std::size_t>(all[at + n]);
        at += n + 1;
    }
}

void serve_candidate_evaluations(ProcessGroup& group, CandidateEvaluator& local, std::size_t dimension) {
    for (;;) {
        std::vector<double> batch;
        group.broadcast(batch);
        if (batch.empty()) return;  // released
        group.gather(score_slice(group, local, batch, dimension));
    }
}

CandidateServers::~CandidateServers() {
    try {
        release();
    } catch (...) {  // an MPI failure here ends the run anyway
    }
}

void CandidateServers::release() {
    if (released_ || group_->size() == 1) return;
    released_ = true;
    std::vector<double> stop;
    group_->broadcast(stop);
}

}  // namespace tvid

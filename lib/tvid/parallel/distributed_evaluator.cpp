#include "tvid/parallel/distributed_evaluator.hpp"

#include <algorithm>
#include <exception>
#include <vector>

namespace tvid {

namespace {

// Scores this process's slice of the broadcast batch.
std::vector<double> score_slice(ProcessGroup& group, CandidateEvaluator& local, const std::vector<double>& batch,
                                std::size_t dimension) {
    const ProcessSlice slice = process_slice(batch.size() / dimension, group.rank(), group.size());
    std::vector<double> costs(slice.size());
    if (slice.size() > 0) local.evaluate(batch.data() + slice.begin * dimension, slice.size(), dimension, costs.data());
    return costs;
}

}  // namespace

DistributedEvaluator::DistributedEvaluator(ProcessGroup* group, CandidateEvaluator& local)
    : group_(group && group->size() > 1 ? group : nullptr), local_(&local) {}

void DistributedEvaluator::evaluate(const double* candidates, std::size_t count, std::size_t dimension, double* costs) {
    if (!group_ || count == 0) {
        if (count > 0) local_->evaluate(candidates, count, dimension, costs);
        return;
    }
    // An empty batch means "stop" to the servers: this one holds count > 0 candidates.
    std::vector<double> batch(candidates, candidates + count * dimension);
    group_->broadcast(batch);
    std::vector<double> mine;
    std::exception_ptr failure;
    try {
        mine = score_slice(*group_, *local_, batch, dimension);
    } catch (...) {
        failure = std::current_exception();  // still take part in the gather the others wait in
        mine.assign(process_slice(count, 0, group_->size()).size(), 0.0);
    }
    const std::vector<double> all = group_->gather(mine);
    if (failure) std::rethrow_exception(failure);
    std::copy(all.begin(), all.end(), costs);
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

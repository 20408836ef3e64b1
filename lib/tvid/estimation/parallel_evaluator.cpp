#include "tvid/estimation/parallel_evaluator.hpp"
#include "tvid/util/parallel_region.hpp"

#include <omp.h>

#include <algorithm>
#include <limits>
#include <thread>

namespace tvid {

int resolve_thread_count(int threads) {
    if (threads > 0) return std::min(threads, kMaxThreads);
    const unsigned hw = std::thread::hardware_concurrency();
    return hw > 0 ? static_cast<int>(hw) : 1;
}

ParallelEvaluator::ParallelEvaluator(const IdentificationProblem& problem, const EvaluatorOptions& options)
    : problem_(&problem), threads_(options.team()), stop_(options.stop) {
    for (int t = 0; t < threads_; ++t) workspaces_.push_back(problem.make_workspace());
    if (batch_supported(problem))
        for (int t = 0; t < threads_; ++t) {
            batch_workspaces_.push_back(std::make_unique<BatchWorkspace>(problem));
            batch_lanes_.push_back(batch_workspaces_.back().get());
        }
    batching_ = !batch_workspaces_.empty();
}

void ParallelEvaluator::evaluate(const double* candidates, std::size_t count, std::size_t dimension, double* costs) {
    evaluate_bounded(candidates, count, dimension, nullptr, costs);
}

void ParallelEvaluator::evaluate_bounded(const double* candidates, std::size_t count, std::size_t dimension,
                                         const double* bounds, double* costs) {
    const double inf = std::numeric_limits<double>::infinity();
    std::atomic<bool> skipped{false};
    if (batching_) {
        stopped_ = !batch_costs(*problem_, candidates, count, bounds, batch_lanes_, stop_, costs);
        return;
    }
    const auto n = static_cast<long long>(count);
    FirstException errors;
#pragma omp parallel for schedule(dynamic, 1) num_threads(threads_)
    for (long long i = 0; i < n; ++i) try {
        if (stop_ && stop_->load(std::memory_order_relaxed)) {
            costs[i] = inf;
            skipped.store(true, std::memory_order_relaxed);
            continue;
        }
        ProblemWorkspace& ws = *workspaces_[static_cast<std::size_t>(omp_get_thread_num())];
        costs[i] = problem_->cost(candidates + static_cast<std::size_t>(i) * dimension, ws, bounds ? bounds[i] : inf);
    } catch (...) {
        errors.capture();
    }
    errors.rethrow();
    stopped_ = skipped.load();
}

std::size_t ParallelEvaluator::right_hand_sides() const {
    std::size_t total = 0;
    for (const auto& ws : workspaces_) total += ws->buffers.rhs_evaluations;
    for (const auto& ws : batch_workspaces_) total += ws->rhs_evaluations + ws->scalar->buffers.rhs_evaluations;
    return total;
}

double ParallelEvaluator::lanes_used() const {
    double needed = 0.0, done = 0.0;
    for (const auto& ws : batch_workspaces_) {
        needed += static_cast<double>(ws->rhs_evaluations);
        done += static_cast<double>(ws->pack_rhs_evaluations) * kBatchLanes;
    }
    return done > 0.0 ? needed / done : 0.0;
}

}  // namespace tvid

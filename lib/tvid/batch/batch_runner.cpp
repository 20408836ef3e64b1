#include "tvid/batch/batch_runner.hpp"

#include <algorithm>
#include <atomic>
#include <exception>
#include <mutex>
#include <thread>

#include "tvid/util/parallel_region.hpp"
#include "tvid/estimation/parallel_evaluator.hpp"
#include "tvid/util/stop_request.hpp"
#include "tvid/util/thread_budget.hpp"

namespace tvid {

void run_batch_jobs(const BatchSettings& settings, const std::vector<BatchJob>& jobs, const NextBatchJob& next,
                    const BatchColumns& columns, int threads, const BatchJobFinished& on_finished) {
    const auto workers = static_cast<std::size_t>(std::max(1, resolve_thread_count(threads)));
    // The cores the running jobs share: once no job is left to start, the last ones take
    // up the cores of the finished (thread_budget.hpp).
    ThreadBudget budget(static_cast<int>(workers));
    std::atomic<bool> stop{false};
    std::mutex finished;
    std::exception_ptr error;
    const auto work = [&] {
        for (;;) {
            if (stop || stop_requested()) return;  // a stop request: no new job starts
            const std::optional<std::size_t> job = next();
            if (!job) return;
            budget.job_started();
            BatchRow row;
            try {
                row = run_batch_job(settings, jobs[*job], columns, &budget);
            } catch (...) {
                budget.job_finished();
                throw;
            }
            budget.job_finished();
            const std::lock_guard<std::mutex> lock(finished);
            if (stop) return;
            try {
                on_finished(*job, row);
            } catch (...) {
                error = std::current_exception();
                stop = true;
            }
        }
    };
    run_on_threads(static_cast<int>(workers), work);  // this thread works too
    if (error) std::rethrow_exception(error);
}

void run_batch_jobs(const BatchSettings& settings, const std::vector<BatchJob>& jobs,
                    const std::vector<std::size_t>& pending, const BatchColumns& columns, int threads,
                    const BatchJobFinished& on_finished) {
    if (pending.empty()) return;
    std::atomic<std::size_t> next{0};
    const NextBatchJob next_pending = [&]() -> std::optional<std::size_t> {
        const std::size_t k = next++;
        if (k >= pending.size()) return std::nullopt;
        return pending[k];
    };
    const int workers = std::min(std::max(1, resolve_thread_count(threads)), static_cast<int>(pending.size()));
    run_batch_jobs(settings, jobs, next_pending, columns, workers, on_finished);
}

}  // namespace tvid

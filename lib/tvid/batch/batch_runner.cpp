#include "tvid/batch/batch_runner.hpp"

#include <algorithm>
#include <atomic>
#include <exception>
#include <mutex>
#include <thread>

#include "tvid/estimation/parallel_evaluator.hpp"

namespace tvid {

void run_batch_jobs(const BatchSettings& settings, const std::vector<BatchJob>& jobs,
                    const std::vector<std::size_t>& pending, const BatchColumns& columns, int threads,
                    const BatchJobFinished& on_finished) {
    if (pending.empty()) return;
    const auto workers = static_cast<std::size_t>(std::max(1, resolve_thread_count(threads)));
    std::atomic<std::size_t> next{0};
    std::atomic<bool> stop{false};
    std::mutex finished;
    std::exception_ptr error;
    const auto work = [&] {
        for (;;) {
            const std::size_t k = next++;
            if (k >= pending.size() || stop) return;
            const BatchRow row = run_batch_job(settings, jobs[pending[k]], columns);
            const std::lock_guard<std::mutex> lock(finished);
            if (stop) return;
            try {
                on_finished(pending[k], row);
            } catch (...) {
                error = std::current_exception();
                stop = true;
            }
        }
    };
    std::vector<std::thread> pool;
    for (std::size_t t = 1; t < std::min(workers, pending.size()); ++t) pool.emplace_back(work);
    work();  // this thread works too
    for (std::thread& t : pool) t.join();
    if (error) std::rethrow_exception(error);
}

}  // namespace tvid

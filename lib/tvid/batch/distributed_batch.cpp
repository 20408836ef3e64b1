#include "tvid/batch/distributed_batch.hpp"

#include <atomic>
#include <exception>
#include <mutex>
#include <stdexcept>
#include <thread>

#include "tvid/estimation/parallel_evaluator.hpp"
#include "tvid/parallel/string_list.hpp"

namespace tvid {

// Messages between a thread of another process (its tag: the thread's number there) and
// the root: the thread sends "" when it starts and then each finished job as the string
// list {job, row cells...}; the root answers each with the next job's number, or "" when
// there is none left, which ends the thread.

std::string encode_batch_plan(const BatchPlan& plan) {
    std::vector<std::string> items{std::to_string(plan.parameters.size())};
    items.insert(items.end(), plan.parameters.begin(), plan.parameters.end());
    items.push_back(std::to_string(plan.outputs.size()));
    items.insert(items.end(), plan.outputs.begin(), plan.outputs.end());
    for (const BatchJob& job : plan.jobs) {
        items.push_back(job.id);
        items.push_back(std::to_string(job.overrides.size()));
        for (const Override& o : job.overrides) {
            items.push_back(o.key);
            items.push_back(o.value);
        }
    }
    return encode_string_list(items);
}

BatchPlan decode_batch_plan(const std::string& message) {
    const std::vector<std::string> items = decode_string_list(message);
    std::size_t at = 0;
    const auto next = [&]() -> const std::string& {
        if (at >= items.size()) throw std::runtime_error("truncated batch plan between processes");
        return items[at++];
    };
    const auto strings = [&](std::vector<std::string>& out) {
        const std::size_t n = std::stoul(next());
        for (std::size_t i = 0; i < n; ++i) out.push_back(next());
    };
    BatchPlan plan;
    strings(plan.parameters);
    strings(plan.outputs);
    while (at < items.size()) {
        BatchJob job{next(), {}};
        const std::size_t n = std::stoul(next());
        for (std::size_t i = 0; i < n; ++i) {
            Override o;
            o.key = next();
            o.value = next();
            job.overrides.push_back(o);
        }
        plan.jobs.push_back(job);
    }
    return plan;
}

void run_batch_jobs_on_group(ProcessGroup& group, const BatchSettings& settings, const std::vector<BatchJob>& jobs,
                             const std::vector<std::size_t>& pending, const BatchColumns& columns, int threads,
                             const BatchJobFinished& on_finished) {
    // How many threads ask from the other processes (the root's own count is not used).
    std::size_t remote_threads = 0;
    for (const std::string& n : group.gather(std::to_string(resolve_thread_count(threads))))
        remote_threads += std::stoul(n);
    remote_threads -= static_cast<std::size_t>(resolve_thread_count(threads));

    // The queue of pending jobs, shared by the root's threads and the other processes.
    std::atomic<std::size_t> next{0};
    std::atomic<bool> closed{false};
    const NextBatchJob next_job = [&]() -> std::optional<std::size_t> {
        if (closed) return std::nullopt;
        const std::size_t k = next++;
        if (k >= pending.size()) return std::nullopt;
        return pending[k];
    };
    // Rows from any thread, one at a time; the first error closes the queue.
    std::mutex delivering;
    std::exception_ptr error;
    const BatchJobFinished deliver = [&](std::size_t job, const BatchRow& row) {
        const std::lock_guard<std::mutex> lock(delivering);
        if (error) return;
        try {
            on_finished(job, row);
        } catch (...) {
            error = std::current_exception();
            closed = true;
        }
    };

    std::exception_ptr local_error;
    std::thread local([&] {
        try {
            run_batch_jobs(settings, jobs, next_job, columns, threads, deliver);
        } catch (...) {
            local_error = std::current_exception();
            closed = true;
        }
    });
    // A row from another process, as run_batch_job made it there.
    const auto receive_row = [&](const std::string& message) {
        try {
            const std::vector<std::string> result = decode_string_list(message);
            if (result.size() != columns.size() + 1) throw std::runtime_error("malformed batch row between processes");
            deliver(std::stoul(result[0]), BatchRow(result.begin() + 1, result.end()));
        } catch (...) {
            const std::lock_guard<std::mutex> lock(delivering);
            if (!error) error = std::current_exception();
            closed = true;
        }
    };
    // This thread serves the other processes until each of their threads has been told to
    // end (also after an error: none of them may be left waiting).
    while (remote_threads > 0) {
        const ProcessGroup::Message m = group.receive(ProcessGroup::any, ProcessGroup::any);
        if (!m.bytes.empty()) receive_row(m.bytes);
        const std::optional<std::size_t> job = next_job();
        group.send(m.source, m.tag, job ? std::to_string(*job) : "");
        if (!job) --remote_threads;
    }
    local.join();
    if (local_error) std::rethrow_exception(local_error);
    if (error) std::rethrow_exception(error);
}

void serve_batch_jobs(ProcessGroup& group, const BatchSettings& settings, const std::vector<BatchJob>& jobs,
                      const BatchColumns& columns, int threads) {
    const int count = resolve_thread_count(threads);
    group.gather(std::to_string(count));
    const auto work = [&](int tag) {
        group.send(0, tag, "");  // ready
        for (;;) {
            const ProcessGroup::Message m = group.receive(0, tag);
            if (m.bytes.empty()) return;
            const std::size_t job = std::stoul(m.bytes);
            std::vector<std::string> result{m.bytes};
            const BatchRow row = run_batch_job(settings, jobs.at(job), columns);
            result.insert(result.end(), row.begin(), row.end());
            group.send(0, tag, encode_string_list(result));
        }
    };
    std::vector<std::thread> pool;
    for (int t = 1; t < count; ++t) pool.emplace_back(work, t);
    work(0);
    for (std::thread& t : pool) t.join();
}

}  // namespace tvid

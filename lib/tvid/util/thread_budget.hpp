#pragma once
// The cores that the running jobs of a batch share. Each parallel region of a job takes
// team() threads: the cores over the jobs running at that moment. While the queue holds
// jobs every core runs one job on one thread; once no job is left to start, the jobs still
// running take up the cores the finished ones left, so no core idles through a batch's
// last, longest jobs. Every result is the same for any thread count, so a job's share may
// change from one region to the next.

#include <algorithm>
#include <atomic>

namespace tvid {

class ThreadBudget {
public:
    explicit ThreadBudget(int cores) : cores_(std::max(1, cores)) {}
    int cores() const { return cores_; }
    void job_started() { running_.fetch_add(1, std::memory_order_relaxed); }
    void job_finished() { running_.fetch_sub(1, std::memory_order_relaxed); }
    /// Threads for one parallel region of a running job.
    int team() const { return std::max(1, cores_ / std::max(1, running_.load(std::memory_order_relaxed))); }

private:
    int cores_;
    std::atomic<int> running_{0};
};

}  // namespace tvid

#pragma once
// Runs the pending jobs of a batch on a pool of threads, one job per thread at a time,
// and hands each finished row to a callback (called by one thread at a time, in the
// order the jobs finish).

#include <cstddef>
#include <functional>
#include <optional>
#include <vector>

#include "tvid/batch/batch_job.hpp"

namespace tvid {

using BatchJobFinished = std::function<void(std::size_t job, const BatchRow& row)>;

/// Runs jobs[i] for every i in `pending` on min(threads, pending) threads (threads <= 0:
/// all cores). If the callback throws, no further job is started and the first such
/// exception is rethrown once the running jobs are done.
void run_batch_jobs(const BatchSettings& settings, const std::vector<BatchJob>& jobs,
                    const std::vector<std::size_t>& pending, const BatchColumns& columns, int threads,
                    const BatchJobFinished& on_finished);

/// The next job to run, or nothing when there is none left. Called by several threads at once.
using NextBatchJob = std::function<std::optional<std::size_t>()>;

/// The same with the jobs drawn from `next` (shared with other workers, e.g. the other
/// processes of an MPI run) on `threads` threads.
void run_batch_jobs(const BatchSettings& settings, const std::vector<BatchJob>& jobs, const NextBatchJob& next,
                    const BatchColumns& columns, int threads, const BatchJobFinished& on_finished);

}  // namespace tvid

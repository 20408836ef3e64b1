#pragma once
// `tvid batch` under mpirun: the root hands out the pending jobs one at a time to
// whichever thread asks next, its own threads and every thread of the other processes
// (dynamic dispatch: a cycle that takes long holds up only the thread fitting it). Rows
// come back to the root, which alone writes batch.csv. Each job is fitted on one thread
// from its own inputs, so every row equals the single-process row.

#include <cstddef>
#include <string>
#include <vector>

#include "tvid/batch/batch_runner.hpp"
#include "tvid/parallel/process_group.hpp"

namespace tvid {

/// What the other processes need to run the root's jobs.
struct BatchPlan {
    std::vector<BatchJob> jobs;
    std::vector<std::string> parameters, outputs;  ///< of the BatchColumns
};

std::string encode_batch_plan(const BatchPlan& plan);
BatchPlan decode_batch_plan(const std::string& message);

/// On the root: runs jobs[i] for every i in `pending` on its `threads` threads and on the
/// threads of every other process (which call serve_batch_jobs meanwhile). `on_finished`
/// runs on the root, one call at a time, in the order the jobs finish; if it throws, no
/// further job is handed out and the exception is rethrown once the running jobs are done.
void run_batch_jobs_on_group(ProcessGroup& group, const BatchSettings& settings, const std::vector<BatchJob>& jobs,
                             const std::vector<std::size_t>& pending, const BatchColumns& columns, int threads,
                             const BatchJobFinished& on_finished);

/// On the other processes: run the jobs the root hands out on `threads` threads (<= 0:
/// all cores) and send the rows back, until the root has no job left.
void serve_batch_jobs(ProcessGroup& group, const BatchSettings& settings, const std::vector<BatchJob>& jobs,
                      const BatchColumns& columns, int threads);

}  // namespace tvid

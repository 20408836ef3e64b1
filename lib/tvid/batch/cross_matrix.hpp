#pragma once
// The cross-cycle matrix of `tvid batch --cross`: every successful job's parameters
// simulated on every successful job's estimation windows (the data that job was fitted
// on), scored by evaluate_parameters like the fit itself, so that the diagonal repeats
// batch.csv's estimation fit % exactly. Written as matrix.csv (wide) and
// matrix_long.csv (one line per cell and output). With an estimated start, a job's start
// corrections belong to its own recording: off the diagonal the validated job's start is
// estimated again with the fitted job's model held, and the cell scores that.

#include <string>
#include <vector>

#include "tvid/batch/batch_job.hpp"

namespace tvid {

struct CrossCell {
    std::vector<double> fit_percent, rmse;  ///< per output, pooled over the validated job's estimation windows
    bool ok = true;                         ///< every window simulated to its end (else the metrics are NaN)
    std::string problem;                    ///< why not, e.g. "estimation window cycle 4: diverged"
};

struct CrossMatrix {
    std::vector<std::string> jobs;              ///< ids of the successful jobs, in job order (rows and columns)
    std::vector<std::string> outputs;           ///< compared outputs
    std::vector<std::vector<CrossCell>> cells;  ///< [fitted][validated]
    bool complete = true;                       ///< false when a stop request cut the work short
};

/// Simulates the parameters of each row with status ok on the estimation windows of each
/// such job (`rows[i]` is the row of `jobs[i]`), one simulation per thread at a time on
/// `threads` threads (<= 0: all cores). Each cell is computed from its own inputs only, so
/// the matrix does not depend on the thread count.
CrossMatrix compute_cross_matrix(const BatchSettings& settings, const std::vector<BatchJob>& jobs,
                                 const std::vector<BatchRow>& rows, const BatchColumns& columns, int threads);

/// Each fitted job's mean fit % on the other jobs' windows (j ≠ i), averaged over the
/// outputs; NaN when it has no finite off-diagonal cell.
std::vector<double> mean_cross_fit(const CrossMatrix& matrix);

/// matrix.csv: `fitted`, then per validated job `fit_ID` and `rmse_ID` (with several
/// outputs `fit_ID_OUT` and `rmse_ID_OUT` per output); one row per fitted job.
std::string cross_matrix_csv(const CrossMatrix& matrix);

/// matrix_long.csv: `fitted,validated,output,fit_percent,rmse,status,problem`.
std::string cross_matrix_long_csv(const CrossMatrix& matrix);

}  // namespace tvid

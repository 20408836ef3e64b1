#pragma once
// batch_summary.json: the spread of each free parameter over the successful jobs (mean,
// standard deviation, min, max), the same for the cost and the Q-indices, job counts,
// wall time and throughput.

#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "tvid/batch/batch_table.hpp"

namespace tvid {

/// Statistics of one column over the rows with status ok and a value in that column.
struct ColumnSpread {
    std::string column;
    std::size_t count = 0;
    double mean = 0.0;
    double std_dev = 0.0;   ///< sample standard deviation (n − 1); NaN when count < 2
    double min = 0.0;
    double max = 0.0;       ///< mean, min, max are NaN when count = 0
};

ColumnSpread column_spread(const std::vector<std::string>& header, const std::vector<BatchRow>& rows,
                           const std::string& column);

struct BatchSummary {
    std::size_t jobs = 0, ok = 0, failed = 0, bad_input = 0;
    std::size_t run = 0;                    ///< jobs run by this invocation (the rest were resumed)
    /// Fitted jobs by verdict: clean, with warnings (no error), with an error.
    std::size_t verdict_clean = 0, verdict_warnings = 0, verdict_errors = 0;
    std::vector<std::string> jobs_with_errors;  ///< their ids, in job order
    std::vector<ColumnSpread> parameters;   ///< per free parameter
    std::vector<ColumnSpread> metrics;      ///< cost and the Q-index columns
    double wall_seconds = 0.0;              ///< of this invocation
    double jobs_per_second = 0.0;           ///< run / wall_seconds; NaN when nothing ran
    int threads = 1;                        ///< per process
    int processes = 1;                      ///< MPI processes that ran jobs (mpirun -n)
};

/// Summarizes the final table (rows in job order, so the sums do not depend on the order
/// in which jobs finished).
BatchSummary summarize_batch(const BatchColumns& columns, const std::vector<BatchRow>& rows, std::size_t run,
                             double wall_seconds, int threads);

struct BatchRunContext {
    std::string version, command_line, experiment, name, output_dir;
};

nlohmann::json batch_summary_json(const BatchSummary& summary, const BatchRunContext& context);

}  // namespace tvid

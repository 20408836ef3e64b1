#pragma once
// One job of `tvid batch`: load the experiment with the job's overrides, fit it on one
// thread and turn the result into a batch.csv row. A job never throws: bad input becomes
// status `bad_input` with the loader's one-line message.

#include <cstdint>
#include <filesystem>
#include <optional>
#include <vector>

#include "tvid/batch/batch_plan.hpp"
#include "tvid/batch/batch_table.hpp"
#include "tvid/fit/fit_run.hpp"

#include "tvid/util/thread_budget.hpp"

namespace tvid {

struct BatchSettings {
    std::filesystem::path experiment;      ///< EXP.yaml
    std::vector<Override> overrides;       ///< the user's --set, before each job's own
    std::optional<std::uint64_t> seed;     ///< --seed (else the experiment's)
};

/// The row of a finished fit: the free parameters (empty when the fit failed), the
/// estimation cost, and Q, fit % and max |residual ratio| pooled per split.
BatchRow fit_row(const BatchColumns& columns, const std::string& id, const IdentificationProblem& problem,
                 const FitResult& fit, double wall_seconds);

/// Runs one job (its result does not depend on how many jobs run at once, nor on its
/// threads): on one thread, or with `budget`, on its share of the batch's cores.
BatchRow run_batch_job(const BatchSettings& settings, const BatchJob& job, const BatchColumns& columns,
                       const ThreadBudget* budget = nullptr);

}  // namespace tvid

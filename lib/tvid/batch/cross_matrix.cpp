#include "tvid/batch/cross_matrix.hpp"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <deque>
#include <exception>
#include <limits>
#include <memory>
#include <thread>

#include "tvid/analysis/evaluation.hpp"
#include "tvid/estimation/parallel_evaluator.hpp"
#include "tvid/estimation/residual_evaluator.hpp"
#include "tvid/optim/held_columns.hpp"
#include "tvid/util/parallel_region.hpp"
#include "tvid/util/stop_request.hpp"

namespace tvid {

namespace {

constexpr double kNoCell = std::numeric_limits<double>::quiet_NaN();

// Runs task(k) for k = 0 … count − 1 on `workers` threads, each task writing only its own
// result; stops handing out tasks on a stop request.
template <class Task>
void for_each_task(std::size_t count, std::size_t workers, const Task& task) {
    std::atomic<std::size_t> next{0};
    const auto work = [&] {
        for (;;) {
            if (stop_requested()) return;
            const std::size_t k = next++;
            if (k >= count) return;
            task(k);
        }
    };
    run_on_threads(static_cast<int>(std::max<std::size_t>(1, std::min(workers, count))), work);
}

// A validated job: its experiment with its own windows, estimation only (the validation
// windows are not part of the data it was fitted on).
struct ValidatedJob {
    std::unique_ptr<Experiment> experiment;
    std::unique_ptr<IdentificationProblem> problem;
    std::vector<std::size_t> start_columns;  ///< its free columns that correct an estimated start
    std::string problem_text;  ///< why it could not be loaded
};

// The free columns of `problem` that correct an estimated start (none without one).
std::vector<std::size_t> start_columns(const IdentificationProblem& problem) {
    std::vector<std::size_t> columns;
    for (const NetworkSpec::StartCoordinate& c : problem.experiment().network.start_coordinates)
        if (const long j = problem.free_column(c.parameter); j >= 0) columns.push_back(static_cast<std::size_t>(j));
    return columns;
}

// Job i's model on job j's windows, where the windows' starts are estimated: job i's start
// corrections belong to its own recordings' seeds, so job j's start is estimated again with
// job i's model held (Levenberg–Marquardt over the start's columns from job j's own fitted
// start, as validation: estimated does for a validation window), and the cell scores that.
// `free_i` holds job i's model values and its start; `free_j` job j's own fit.
std::vector<double> start_estimated_with_model_held(const IdentificationProblem& problem,
                                                    const std::vector<std::size_t>& starts, std::vector<double> free_i,
                                                    const std::vector<double>& free_j, std::string* why) {
    std::vector<double> x0, lower, upper;
    for (std::size_t j : starts) {
        free_i[j] = free_j[j];
        x0.push_back(free_j[j]);
        lower.push_back(problem.lower()[j]);
        upper.push_back(problem.upper()[j]);
    }
    ResidualEvaluator whole(problem, EvaluatorOptions(1));
    HeldColumns start(whole, free_i, starts);
    LmSettings settings;
    settings.max_iterations = 60;
    settings.stol = 0.0;  // the start to the bit the data give, not to a standard error
    const LmSummary fit = run_levenberg_marquardt(settings, x0, lower, upper, start);
    if (!std::isfinite(fit.best_cost) || fit.best.size() != starts.size()) {
        if (why) *why = "the start could not be estimated with the model held: " + fit.termination;
        return free_i;  // job j's own start: the cell says it failed
    }
    return start.whole_point(fit.best.data());
}

}  // namespace

CrossMatrix compute_cross_matrix(const BatchSettings& settings, const std::vector<BatchJob>& jobs,
                                 const std::vector<BatchRow>& rows, const BatchColumns& columns, int threads) {
    CrossMatrix m;
    std::vector<std::size_t> index;  // job index of each matrix row/column
    for (std::size_t j = 0; j < jobs.size() && j < rows.size(); ++j)
        if (rows[j][1] == kBatchOk) {
            index.push_back(j);
            m.jobs.push_back(jobs[j].id);
        }
    const std::size_t n = index.size();
    const auto workers = static_cast<std::size_t>(std::max(1, resolve_thread_count(threads)));

    std::vector<ValidatedJob> validated(n);
    for_each_task(n, workers, [&](std::size_t k) {
        std::vector<Override> overrides = settings.overrides;
        overrides.insert(overrides.end(), jobs[index[k]].overrides.begin(), jobs[index[k]].overrides.end());
        overrides.push_back(Override{"windows.validation", "[]"});
        try {
            validated[k].experiment = std::make_unique<Experiment>(load_experiment(settings.experiment, overrides));
            validated[k].problem = std::make_unique<IdentificationProblem>(*validated[k].experiment);
            validated[k].start_columns = start_columns(*validated[k].problem);
        } catch (const std::exception& e) {
            validated[k].problem_text = e.what();
        }
    });
    if (stop_requested()) {
        m.complete = false;
        return m;
    }
    for (const ValidatedJob& v : validated)
        if (v.experiment) {
            for (const ChannelBinding& o : v.experiment->outputs) m.outputs.push_back(o.model_name);
            break;
        }

    // The fitted free parameters, read back from the rows (17 digits: exactly the fit's).
    std::vector<std::vector<double>> free(n);
    for (std::size_t i = 0; i < n; ++i)
        for (const std::string& p : columns.parameters())
            free[i].push_back(batch_cell_value(rows[index[i]][columns.index(p)]));

    m.cells.assign(n, std::vector<CrossCell>(n));
    std::vector<std::atomic<bool>> done(n * n);
    for_each_task(n * n, workers, [&](std::size_t task) {
        const std::size_t i = task / n, j = task % n;
        CrossCell& cell = m.cells[i][j];
        cell.fit_percent.assign(m.outputs.size(), kNoCell);
        cell.rmse.assign(m.outputs.size(), kNoCell);
        const ValidatedJob& v = validated[j];
        if (!v.problem) {
            cell.ok = false;
            cell.problem = v.problem_text;
        } else {
            try {
                const std::vector<std::size_t>& starts = v.start_columns;
                std::string start_problem;
                const std::vector<double> point =
                    i == j || starts.empty()
                        ? free[i]
                        : start_estimated_with_model_held(*v.problem, starts, free[i], free[j], &start_problem);
                const Evaluation ev = evaluate_parameters(*v.problem, v.problem->full_parameters(point), 1);
                cell.ok = ev.estimation.ok && start_problem.empty();
                cell.problem = start_problem.empty() ? first_failed_window(ev) : start_problem;
                for (std::size_t k = 0; cell.ok && k < m.outputs.size() && k < ev.estimation.pooled.size(); ++k) {
                    cell.fit_percent[k] = ev.estimation.pooled[k].fit_percent;
                    cell.rmse[k] = ev.estimation.pooled[k].rmse;
                }
            } catch (const std::exception& e) {
                cell.ok = false;
                cell.problem = e.what();
            }
        }
        done[task] = true;
    });
    m.complete = std::all_of(done.begin(), done.end(), [](const std::atomic<bool>& d) { return d.load(); });
    return m;
}

std::vector<double> mean_cross_fit(const CrossMatrix& m) {
    std::vector<double> out(m.jobs.size(), kNoCell);
    for (std::size_t i = 0; i < m.cells.size(); ++i) {
        double sum = 0.0;
        std::size_t count = 0;
        for (std::size_t j = 0; j < m.cells[i].size(); ++j) {
            if (j == i) continue;
            for (double f : m.cells[i][j].fit_percent)
                if (std::isfinite(f)) {
                    sum += f;
                    ++count;
                }
        }
        if (count > 0) out[i] = sum / static_cast<double>(count);
    }
    return out;
}

std::string cross_matrix_csv(const CrossMatrix& m) {
    const bool several = m.outputs.size() > 1;
    BatchRow header{"fitted"};
    for (const std::string& id : m.jobs)
        for (const std::string& out : m.outputs) {
            const std::string suffix = id + (several ? "_" + out : "");
            header.push_back("fit_" + suffix);
            header.push_back("rmse_" + suffix);
        }
    std::string text = batch_csv_line(header);
    for (std::size_t i = 0; i < m.cells.size(); ++i) {
        BatchRow row{m.jobs[i]};
        for (const CrossCell& cell : m.cells[i])
            for (std::size_t k = 0; k < m.outputs.size(); ++k) {
                row.push_back(batch_number(cell.fit_percent[k]));
                row.push_back(batch_number(cell.rmse[k]));
            }
        text += batch_csv_line(row);
    }
    return text;
}

std::string cross_matrix_long_csv(const CrossMatrix& m) {
    std::string text = batch_csv_line({"fitted", "validated", "output", "fit_percent", "rmse", "status", "problem"});
    for (std::size_t i = 0; i < m.cells.size(); ++i)
        for (std::size_t j = 0; j < m.cells[i].size(); ++j) {
            const CrossCell& cell = m.cells[i][j];
            for (std::size_t k = 0; k < m.outputs.size(); ++k)
                text += batch_csv_line({m.jobs[i], m.jobs[j], m.outputs[k], batch_number(cell.fit_percent[k]),
                                        batch_number(cell.rmse[k]), cell.ok ? "ok" : "failed", cell.problem});
        }
    return text;
}

}  // namespace tvid

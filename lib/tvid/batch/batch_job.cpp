#include "tvid/batch/batch_job.hpp"

#include <chrono>
#include <cstdio>
#include <exception>

#include "tvid/util/input_error.hpp"
#include "tvid/util/stop_request.hpp"

namespace tvid {

namespace {

// Why a split's windows failed to simulate, e.g. "validation cycle 4: diverged".
std::string window_problems(const SplitEvaluation& split) {
    std::string out;
    for (const WindowEvaluation& w : split.windows) {
        if (w.trace.status == SimulationStatus::ok) continue;
        out += (out.empty() ? "" : "; ") + split.split + " " + (w.trace.window ? w.trace.window->label : "window") +
               ": " + (w.trace.problem.empty() ? to_string(w.trace.status) : w.trace.problem);
    }
    return out;
}

// Seconds to the millisecond: a timing, not a result to read back exactly.
std::string wall_time_text(double seconds) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.3f", seconds);
    return buf;
}

// The loader names an override "--set"; a job's own overrides came from --data or --cycles.
std::string batch_input_message(const InputError& e, const BatchJob& job) {
    if (e.file() != "--set") return e.what();
    for (const Override& o : job.overrides)
        if (e.key().rfind(o.key, 0) == 0)
            return InputError(o.key == "data.file" ? "--data" : "--cycles", 0, e.key(), e.problem()).what();
    return e.what();
}

}  // namespace

BatchRow fit_row(const BatchColumns& columns, const std::string& id, const IdentificationProblem& problem,
                 const FitResult& fit, double wall_seconds) {
    const Experiment& ex = problem.experiment();
    std::string message = fit.run.termination;
    if (fit.success)
        for (const SplitEvaluation* split : {&fit.evaluation.estimation, &fit.evaluation.validation})
            if (const std::string why = window_problems(*split); !why.empty()) message += "; " + why;
    BatchRow row = columns.row(id, fit.success ? kBatchOk : kBatchFailed, message);
    row[columns.index("evaluations")] = std::to_string(fit.run.evaluations);
    row[columns.index("wall_seconds")] = wall_time_text(wall_seconds);
    row[columns.index("verdict")] = fit.verdict.summary();
    std::string findings;
    for (const Finding& f : fit.verdict.findings) {
        if (f.severity == Severity::info) continue;
        findings += (findings.empty() ? "" : ";") + std::string(to_string(f.severity)) + ":" + f.code +
                    (f.subject.empty() ? "" : "(" + f.subject + ")");
    }
    row[columns.index("findings")] = findings;
    if (!fit.success) return row;  // no estimate: parameters and metrics stay empty

    for (std::size_t j = 0; j < problem.dimension(); ++j)
        row[columns.index(problem.free_names()[j])] = batch_number(fit.best_free[j]);
    row[columns.index("cost")] = batch_number(fit.run.best_cost);
    for (const SplitEvaluation* split : {&fit.evaluation.estimation, &fit.evaluation.validation}) {
        if (split->windows.empty()) continue;  // no validation windows: the cells stay empty
        for (std::size_t k = 0; k < ex.outputs.size() && k < split->pooled.size(); ++k) {
            const FitMetrics& m = split->pooled[k];
            const std::string& out = ex.outputs[k].model_name;
            row[columns.index(columns.metric("q", split->split, out))] = batch_number(m.q_index);
            row[columns.index(columns.metric("fit", split->split, out))] = batch_number(m.fit_percent);
            row[columns.index(columns.metric("max_residual_ratio_percent", split->split, out))] =
                batch_number(100.0 * m.max_abs_residual_ratio);
        }
    }
    return row;
}

BatchRow run_batch_job(const BatchSettings& settings, const BatchJob& job, const BatchColumns& columns,
                       const ThreadBudget* budget) {
    using clock = std::chrono::steady_clock;
    const auto start = clock::now();
    const auto seconds = [&] { return std::chrono::duration<double>(clock::now() - start).count(); };
    const auto stopped = [&](const char* status, const std::string& message) {
        BatchRow row = columns.row(job.id, status, message);
        row[columns.index("wall_seconds")] = wall_time_text(seconds());
        return row;
    };
    std::vector<Override> overrides = settings.overrides;
    overrides.insert(overrides.end(), job.overrides.begin(), job.overrides.end());
    try {
        const Experiment ex = load_experiment(settings.experiment, overrides);
        const IdentificationProblem problem(ex);
        if (problem.free_names() != columns.parameters())
            return stopped(kBatchBadInput, "the free parameters differ from those of the batch's experiment");
        FitOptions options;
        options.threads = 1;
        options.budget = budget;
        options.seed = settings.seed;
        options.stop = &stop_request();
        const FitResult fit = run_fit(problem, options);
        if (fit.interrupted || stop_requested()) return stopped(kBatchInterrupted, "stopped by a stop request before its fit finished");
        return fit_row(columns, job.id, problem, fit, seconds());
    } catch (const InputError& e) {
        return stopped(kBatchBadInput, batch_input_message(e, job));
    } catch (const std::exception& e) {
        return stopped(kBatchFailed, std::string("tvid: ") + e.what());
    }
}

}  // namespace tvid

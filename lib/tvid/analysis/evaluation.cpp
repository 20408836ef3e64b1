#include "tvid/analysis/evaluation.hpp"
#include "tvid/util/parallel_region.hpp"

#include <omp.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>

namespace tvid {

namespace {

// Fit metrics per window and output, and pooled over the split's windows.
SplitEvaluation assemble_split(const IdentificationProblem& problem, std::vector<WindowTrace> traces, const char* name,
                               const std::vector<double>& offsets) {
    SplitEvaluation split;
    split.split = name;
    const std::size_t n_out = problem.experiment().outputs.size();
    std::vector<std::vector<double>> all_measured(n_out), all_simulated(n_out);
    for (WindowTrace& trace : traces) {
        WindowEvaluation we;
        we.trace = std::move(trace);
        if (we.trace.status != SimulationStatus::ok) split.ok = false;
        for (std::size_t k = 0; k < n_out; ++k) {
            we.metrics.push_back(compute_fit_metrics(we.trace.measured[k], we.trace.simulated[k], offsets[k]));
            all_measured[k].insert(all_measured[k].end(), we.trace.measured[k].begin(), we.trace.measured[k].end());
            all_simulated[k].insert(all_simulated[k].end(), we.trace.simulated[k].begin(), we.trace.simulated[k].end());
        }
        split.windows.push_back(std::move(we));
    }
    for (std::size_t k = 0; k < n_out; ++k) {
        split.pooled.push_back(compute_fit_metrics(all_measured[k], all_simulated[k], offsets[k]));
        // The residual ratio's floor is each window's own (fit_metrics.hpp): the pooled
        // figure is the largest of the windows'.
        if (split.pooled.back().samples == 0) continue;
        double largest = 0.0, smallest_y = std::numeric_limits<double>::quiet_NaN();
        for (const WindowEvaluation& w : split.windows) {
            if (w.metrics[k].samples == 0) continue;
            largest = std::max(largest, w.metrics[k].max_abs_residual_ratio);
            const double y = w.metrics[k].residual_ratio_min_abs_y;
            if (std::isfinite(y) && !(y >= smallest_y)) smallest_y = y;
        }
        split.pooled.back().max_abs_residual_ratio = largest;
        split.pooled.back().residual_ratio_min_abs_y = smallest_y;
    }
    return split;
}

}  // namespace

Evaluation evaluate_parameters(const IdentificationProblem& problem, const std::vector<double>& params, int threads) {
    Evaluation ev;
    ev.params = params;
    const Experiment& ex = problem.experiment();
    const std::size_t n_est = ex.estimation.size(), n_val = ex.validation.size();
    // One task per window, then the estimation cost from the starts the estimation windows'
    // traces solved (the same value as solving them again). Each task simulates from its
    // own inputs only, so the results do not depend on which thread ran it.
    const std::size_t tasks = n_est + n_val;
    const int team = static_cast<int>(std::min<std::size_t>(static_cast<std::size_t>(std::max(1, threads)), tasks));
    std::vector<std::unique_ptr<ProblemWorkspace>> workspaces;
    for (int t = 0; t < team; ++t) {
        workspaces.push_back(problem.make_workspace());
        workspaces.back()->params = params;  // fixed parameters as given; cost() overwrites only the free ones
        workspaces.back()->model.set_parameters(params.data());
    }
    for (std::size_t k = 0; k < ex.outputs.size(); ++k)
        ev.output_offsets.push_back(
            workspaces[0]->model.output_offset(static_cast<std::size_t>(ex.output_indices[k])));
    ev.output_scale = problem.definition().output_scale;
    ev.output_spread = problem.definition().output_spread;
    ev.normalized = problem.definition().normalized;
    std::vector<double> free;
    for (std::size_t j : problem.free_indices()) free.push_back(params[j]);

    std::vector<WindowTrace> estimation(n_est), validation(n_val);
    ev.estimation_starts.resize(n_est);
    const auto n_tasks = static_cast<long long>(tasks);
    FirstException errors;
#pragma omp parallel for schedule(dynamic, 1) num_threads(team)
    for (long long task = 0; task < n_tasks; ++task) try {
        ProblemWorkspace& ws = *workspaces[static_cast<std::size_t>(omp_get_thread_num())];
        const auto i = static_cast<std::size_t>(task);
        if (i < n_est)
            estimation[i] = problem.trace(params, ex.estimation[i], ws, &ev.estimation_starts[i]);
        else
            validation[i - n_est] = problem.trace(params, ex.validation[i - n_est], ws);
    } catch (...) {
        errors.capture();
    }
    errors.rethrow();
    for (std::size_t i = 0; i < n_est; ++i)  // a failed window's start is solved again, and fails again
        if (estimation[i].status != SimulationStatus::ok) ev.estimation_starts[i] = SolvedStart{};
    ev.cost = problem.cost(free.data(), *workspaces[0], ev.estimation_starts);
    ev.estimation = assemble_split(problem, std::move(estimation), "estimation", ev.output_offsets);
    ev.validation = assemble_split(problem, std::move(validation), "validation", ev.output_offsets);
    return ev;
}

std::string first_failed_window(const Evaluation& ev) {
    for (const SplitEvaluation* split : {&ev.estimation, &ev.validation})
        for (const WindowEvaluation& w : split->windows) {
            if (w.trace.status == SimulationStatus::ok) continue;
            std::string why = w.trace.problem.empty() ? to_string(w.trace.status) : w.trace.problem;
            if (why.rfind("simulation ", 0) == 0) why.erase(0, 11);  // "simulation diverged" -> "diverged"
            return split->split + " window " + w.trace.window->label + ": " + why;
        }
    return "";
}

int failed_window_count(const Evaluation& ev) {
    int failed = 0;
    for (const SplitEvaluation* split : {&ev.estimation, &ev.validation})
        for (const WindowEvaluation& w : split->windows) failed += w.trace.status == SimulationStatus::ok ? 0 : 1;
    return failed;
}

}  // namespace tvid

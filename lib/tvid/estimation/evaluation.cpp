#include "tvid/estimation/evaluation.hpp"

namespace tvid {

namespace {

SplitEvaluation evaluate_split(const IdentificationProblem& problem, const std::vector<double>& params,
                               const std::vector<Window>& windows, const char* name,
                               const std::vector<double>& offsets, ProblemWorkspace& ws) {
    SplitEvaluation split;
    split.split = name;
    const std::size_t n_out = problem.experiment().outputs.size();
    std::vector<std::vector<double>> all_measured(n_out), all_simulated(n_out);
    for (const Window& w : windows) {
        WindowEvaluation we;
        we.trace = problem.trace(params, w, ws);
        if (we.trace.status != SimulationStatus::ok) split.ok = false;
        for (std::size_t k = 0; k < n_out; ++k) {
            we.metrics.push_back(compute_fit_metrics(we.trace.measured[k], we.trace.simulated[k], offsets[k]));
            all_measured[k].insert(all_measured[k].end(), we.trace.measured[k].begin(), we.trace.measured[k].end());
            all_simulated[k].insert(all_simulated[k].end(), we.trace.simulated[k].begin(), we.trace.simulated[k].end());
        }
        split.windows.push_back(std::move(we));
    }
    for (std::size_t k = 0; k < n_out; ++k)
        split.pooled.push_back(compute_fit_metrics(all_measured[k], all_simulated[k], offsets[k]));
    return split;
}

}  // namespace

Evaluation evaluate_parameters(const IdentificationProblem& problem, const std::vector<double>& params) {
    Evaluation ev;
    ev.params = params;
    auto ws = problem.make_workspace();
    ws->params = params;  // fixed parameters as given; cost() overwrites only the free ones
    ws->model.set_parameters(params.data());
    const Experiment& ex = problem.experiment();
    for (std::size_t k = 0; k < ex.outputs.size(); ++k)
        ev.output_offsets.push_back(ws->model.output_offset(static_cast<std::size_t>(ex.output_indices[k])));
    std::vector<double> free;
    for (std::size_t j : problem.free_indices()) free.push_back(params[j]);
    ev.cost = problem.cost(free.data(), *ws);
    ev.estimation = evaluate_split(problem, params, ex.estimation, "estimation", ev.output_offsets, *ws);
    ev.validation = evaluate_split(problem, params, ex.validation, "validation", ev.output_offsets, *ws);
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

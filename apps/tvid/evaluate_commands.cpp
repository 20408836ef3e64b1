// `tvid simulate` and `tvid validate`: run the model with a given parameter set.

#include <iostream>
#include <sstream>

#include "commands.hpp"
#include "tvid/analysis/evaluation.hpp"
#include "tvid/estimation/parallel_evaluator.hpp"
#include "tvid/experiment/experiment.hpp"
#include "tvid/io/atomic_file.hpp"
#include "tvid/report/parameter_file.hpp"
#include "tvid/report/report_writer.hpp"
#include "tvid/io/json_text.hpp"

namespace tvid::cli {

std::vector<Override> parse_overrides(const std::vector<std::string>& texts);

namespace {

std::vector<double> chosen_parameters(const EvaluateCommand& cmd, const Experiment& ex) {
    return cmd.params_file.empty() ? initial_parameters(ex) : read_parameter_file(cmd.params_file, ex);
}

// Exit status 1 with one line on stderr naming the first window whose simulation failed
// (diverged, not finite, step budget exceeded); 0 when every window simulated.
int report_failed_windows(const Evaluation& ev) {
    const int failed = failed_window_count(ev);
    if (failed == 0) return 0;
    std::cerr << "tvid: the simulation failed in " << first_failed_window(ev)
              << (failed > 1 ? " (and in " + std::to_string(failed - 1) + " more window(s))" : "") << '\n';
    return 1;
}

}  // namespace

int run_simulate_command(const EvaluateCommand& cmd) {
    const Experiment ex = load_experiment(cmd.common.experiment, parse_overrides(cmd.common.overrides));
    const IdentificationProblem problem(ex);
    const Evaluation ev = evaluate_parameters(problem, chosen_parameters(cmd, ex), resolve_thread_count(cmd.common.threads));
    std::string csv = trace_csv(ex, ev.estimation);
    if (!ev.validation.windows.empty()) {
        const std::string more = trace_csv(ex, ev.validation);
        csv += more.substr(more.find('\n') + 1);  // same header
    }
    if (cmd.output.empty()) {
        std::cout << csv;
    } else {
        write_file_atomically(cmd.output, csv);
    }
    return report_failed_windows(ev);
}

int run_validate_command(const EvaluateCommand& cmd) {
    const Experiment ex = load_experiment(cmd.common.experiment, parse_overrides(cmd.common.overrides));
    const IdentificationProblem problem(ex);
    const Evaluation ev = evaluate_parameters(problem, chosen_parameters(cmd, ex), resolve_thread_count(cmd.common.threads));
    nlohmann::json j{{"experiment", ex.name},
                     {"cost", std::isfinite(ev.cost) ? nlohmann::json(ev.cost) : nlohmann::json(nullptr)},
                     {"estimation", split_json(ex, ev.estimation)},
                     {"validation", split_json(ex, ev.validation)}};
    if (!cmd.output.empty()) write_file_atomically(cmd.output, json_text(j) + "\n");
    if (cmd.common.json || cmd.output.empty()) std::cout << json_text(j) << std::endl;
    return report_failed_windows(ev);
}

}  // namespace tvid::cli

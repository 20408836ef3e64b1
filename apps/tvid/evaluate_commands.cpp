// `tvid simulate` and `tvid validate`: run the model with a given parameter set.

#include <iostream>
#include <sstream>

#include <memory>

#include "command_options.hpp"
#include "command_table.hpp"
#include "commands.hpp"
#include "tvid/experiment/overrides.hpp"
#include "terminal.hpp"
#include "tvid/analysis/evaluation.hpp"
#include "tvid/estimation/parallel_evaluator.hpp"
#include "tvid/experiment/experiment.hpp"
#include "tvid/experiment/window_recording.hpp"
#include "tvid/io/atomic_file.hpp"
#include "tvid/io/output_directory.hpp"
#include "tvid/report/parameter_file.hpp"
#include "tvid/report/report_writer.hpp"
#include "tvid/io/json_text.hpp"
#include "tvid/report/report_values.hpp"

namespace tvid::cli {


namespace {

// --params, or the experiment's own values. An estimated start is read as stored, against
// this experiment's seeds; a start it cannot use is said on stderr.
std::vector<double> chosen_parameters(const EvaluateCommand& cmd, const Experiment& ex, const IdentificationProblem& problem) {
    if (cmd.params_file.empty()) return initial_parameters(ex);
    std::vector<std::string> notes;
    std::vector<double> p = read_parameter_file(cmd.params_file, ex, &problem.definition().estimated.seed, &notes);
    for (const std::string& note : notes) std::cerr << "tvid: note: " << note << '\n';
    return p;
}

// Exit status 1 with one line on stderr naming the first window whose simulation failed
// (diverged, not finite, step budget exceeded); 0 when every window simulated.
int report_failed_windows(const Evaluation& ev) {
    const int failed = failed_window_count(ev);
    if (failed == 0) return kExitDone;
    std::cerr << "tvid: the simulation failed in " << first_failed_window(ev)
              << (failed > 1 ? " (and in " + std::to_string(failed - 1) + " more window(s))" : "") << '\n';
    return kExitNotSucceeded;
}

// The metrics of a parameter set as `tvid validate --json` prints them.
nlohmann::json evaluation_json(const Experiment& ex, const Evaluation& ev) {
    return {{"experiment", ex.name},
            {"cost", std::isfinite(ev.cost) ? nlohmann::json(ev.cost) : nlohmann::json(nullptr)},
            {"estimation", split_json(ex, ev.estimation)},
            {"validation", split_json(ex, ev.validation)}};
}

// Every scored sample of a split as columns: t, window, and per output measured and
// simulated (the CSV's content, for `tvid simulate --json`).
nlohmann::json traces_json(const Experiment& ex, const SplitEvaluation& split) {
    nlohmann::json t = nlohmann::json::array(), window = nlohmann::json::array(), outputs = nlohmann::json::object();
    for (const ChannelBinding& o : ex.outputs)
        outputs[o.model_name] = {{"measured", nlohmann::json::array()}, {"simulated", nlohmann::json::array()}};
    for (const WindowEvaluation& w : split.windows)
        for (std::size_t i = 0; i < w.trace.time.size(); ++i) {
            t.push_back(recording_time(ex, *w.trace.window, w.trace.time[i]));
            window.push_back(w.trace.window->label);
            for (std::size_t k = 0; k < ex.outputs.size() && k < w.trace.measured.size(); ++k) {
                nlohmann::json& o = outputs[ex.outputs[k].model_name];
                o["measured"].push_back(json_number(w.trace.measured[k][i]));
                o["simulated"].push_back(json_number(w.trace.simulated[k][i]));
            }
        }
    return {{"t", t}, {"window", window}, {"outputs", outputs}};
}

// Where the command's file goes: -o FILE, or its default name in --output-dir DIR; empty
// for none (stdout). -o naming a folder is refused (check_output_target): nothing
// replaces a folder.
std::filesystem::path output_file(const EvaluateCommand& cmd, const char* default_name) {
    if (!cmd.output_dir.empty()) return std::filesystem::path(cmd.output_dir) / default_name;
    return cmd.output;
}

// --output-dir DIR: created, checked and claimed before the work, as a report directory is.
OutputDirectoryLock prepare_named_output_dir(const EvaluateCommand& cmd, const std::string& default_name) {
    if (cmd.output_dir.empty()) return {};
    return prepare_output_directory(cmd.output_dir, "output directory", {default_name});
}

// What every file of the kind holds (atomic_file.hpp's check_replaceable).
constexpr WrittenFileMark kSimulationCsvMark{WrittenFileMark::Form::csv_heading, "t [s],window,", ""};
constexpr WrittenFileMark kValidationJsonMark{WrittenFileMark::Form::json_string, "written_by", "tvid validate"};

}  // namespace

int run_simulate_command(const EvaluateCommand& cmd) {
    const Experiment ex = load_experiment(cmd.common.experiment, parse_overrides(cmd.common.overrides));
    const IdentificationProblem problem(ex);
    const std::vector<double> params = chosen_parameters(cmd, ex, problem);
    // Before the work: the file must be a place for a new file or one tvid wrote, not a
    // FIFO, a file this run reads or a user's file (without --force).
    const std::filesystem::path target = output_file(cmd, "simulation.csv");
    const OutputDirectoryLock lock = prepare_named_output_dir(cmd, "simulation.csv");
    if (!target.empty()) check_replaceable(target, cmd.force, kSimulationCsvMark, "a simulation CSV");
    const Evaluation ev = evaluate_parameters(problem, params, resolve_thread_count(cmd.common.threads));
    std::string csv = trace_csv(ex, ev.estimation);
    if (!ev.validation.windows.empty()) {
        const std::string more = trace_csv(ex, ev.validation);
        csv += more.substr(more.find('\n') + 1);  // same header
    }
    // The CSV goes to -o, else to stdout (for a pipe); --json prints the same samples with
    // the metrics as JSON instead, and with -o the terminal gets the summary table.
    if (!target.empty()) write_named_output_file(target, csv);
    if (cmd.common.json) {
        nlohmann::json j = evaluation_json(ex, ev);
        j["traces"] = {{"estimation", traces_json(ex, ev.estimation)}, {"validation", traces_json(ex, ev.validation)}};
        std::cout << json_text(j) << std::endl;
    } else if (target.empty()) {
        std::cout << csv;
    } else if (!cmd.common.quiet) {
        std::cout << evaluation_summary_text("simulate", ex, ev) << "  written: " << target.string() << "\n" << std::flush;
    }
    return report_failed_windows(ev);
}

int run_validate_command(const EvaluateCommand& cmd) {
    const Experiment ex = load_experiment(cmd.common.experiment, parse_overrides(cmd.common.overrides));
    const IdentificationProblem problem(ex);
    const std::vector<double> params = chosen_parameters(cmd, ex, problem);
    const std::filesystem::path target = output_file(cmd, "validation.json");
    const OutputDirectoryLock lock = prepare_named_output_dir(cmd, "validation.json");
    if (!target.empty()) check_replaceable(target, cmd.force, kValidationJsonMark, "a validation JSON");
    const Evaluation ev = evaluate_parameters(problem, params, resolve_thread_count(cmd.common.threads));
    nlohmann::json j = evaluation_json(ex, ev);
    j["written_by"] = "tvid validate";
    if (!target.empty()) write_named_output_file(target, json_text(j) + "\n");
    // The table as `tvid fit` prints it; the JSON with --json.
    if (cmd.common.json) std::cout << json_text(j) << std::endl;
    else if (!cmd.common.quiet) std::cout << evaluation_summary_text("validate", ex, ev) << std::flush;
    return report_failed_windows(ev);
}

CommandRow simulate_command_row() {
    return {"simulate", "simulate every window and print measured vs simulated as CSV", false,
            [](CLI::App& sub) -> CommandRunner {
                auto simulate = std::make_shared<EvaluateCommand>();
                add_common(sub, simulate->common);
                sub.add_option("--params", simulate->params_file, "parameter file (params.json of a fit, or {name: value})");
                add_file_output(sub, *simulate, "the CSV", "simulation.csv");
                return [simulate](const CommandContext& context) {
                    simulate->common.command_line = context.command_line;
                    return run_simulate_command(*simulate);
                };
            }};
}

CommandRow validate_command_row() {
    return {"validate", "score a parameter set on the estimation and validation windows", false,
            [](CLI::App& sub) -> CommandRunner {
                auto validate = std::make_shared<EvaluateCommand>();
                add_common(sub, validate->common);
                sub.add_option("--params", validate->params_file, "parameter file")->required();
                add_file_output(sub, *validate, "the JSON", "validation.json");
                return [validate](const CommandContext& context) {
                    validate->common.command_line = context.command_line;
                    return run_validate_command(*validate);
                };
            }};
}

}  // namespace tvid::cli

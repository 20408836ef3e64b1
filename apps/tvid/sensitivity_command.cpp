// `tvid sensitivity EXP.yaml`: how the outputs respond to each free parameter (the methodology paper
// Figs. 4–5), from forward sensitivities at one parameter set, and a ranking.

#include <omp.h>

#include <algorithm>
#include <chrono>
#include <iostream>
#include <memory>

#include "command_options.hpp"
#include "command_table.hpp"
#include "commands.hpp"
#include "tvid/report/report_directory.hpp"
#include "tvid/experiment/overrides.hpp"
#include "terminal.hpp"
#include "tvid/estimation/residual_evaluator.hpp"
#include "tvid/util/parallel_region.hpp"
#include "tvid/estimation/identification_problem.hpp"
#include "tvid/estimation/parallel_evaluator.hpp"
#include "tvid/experiment/experiment.hpp"
#include "tvid/report/parameter_file.hpp"
#include "tvid/io/output_directory.hpp"
#include "tvid/report/sensitivity_report.hpp"
#include "tvid/util/input_error.hpp"
#include "tvid/io/json_text.hpp"

namespace tvid::cli {


int run_sensitivity_command(const SensitivityCommand& cmd) {
    const Experiment ex = load_experiment(cmd.common.experiment, parse_overrides(cmd.common.overrides));
    const IdentificationProblem problem(ex);
    if (problem.dimension() == 0)
        throw InputError(ex.file.string(), 0, "parameters", "every parameter is fixed: there is no sensitivity to compute");
    const std::vector<double> params =
        cmd.params_file.empty() ? initial_parameters(ex) : read_parameter_file(cmd.params_file, ex);
    std::vector<double> free;
    for (std::size_t i : problem.free_indices()) free.push_back(params[i]);
    const std::filesystem::path dir =
        cmd.output_dir.empty() ? report_directory(ex, "") / "sensitivity" : std::filesystem::path(cmd.output_dir);
    // Before the work: an unusable place is bad input, and this run holds it until written.
    const OutputDirectoryLock lock = prepare_output_directory(dir, "sensitivity directory", {"sensitivity.csv", "ranking.csv", "sensitivity.json"},
                                                              "sensitivity.json", cmd.force);

    std::vector<const Window*> windows;
    for (const Window& w : ex.estimation) windows.push_back(&w);
    if (cmd.validation)
        for (const Window& w : ex.validation) windows.push_back(&w);

    // One window per task, each thread with its own workspace of the one evaluator: a
    // window's sensitivities do not depend on the thread count.
    const int threads = std::max(1, std::min(resolve_thread_count(cmd.common.threads), static_cast<int>(windows.size())));
    ResidualEvaluator evaluator(problem, EvaluatorOptions(threads).with_jacobian(JacobianKind::sensitivity));
    std::vector<WindowSensitivity> results(windows.size());
    const auto start = std::chrono::steady_clock::now();
    const auto n = static_cast<long long>(windows.size());
    FirstException errors;
#pragma omp parallel for schedule(dynamic, 1) num_threads(threads)
    for (long long i = 0; i < n; ++i) {
        errors.run([&] {
            const auto w = static_cast<std::size_t>(i);
            results[w] = evaluator.output_sensitivity(free.data(), *windows[w], omp_get_thread_num());
        });
    }
    errors.rethrow();
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();

    for (std::size_t w = 0; w < results.size(); ++w) {
        if (results[w].status == SimulationStatus::ok) continue;
        const char* split = w < ex.estimation.size() ? "estimation" : "validation";
        const std::string why = results[w].problem.empty() ? to_string(results[w].status) : results[w].problem;
        std::cerr << "tvid: the simulation of " << split << " window " << windows[w]->label << " failed: " << why
                  << "; nothing written\n";
        return kExitNotSucceeded;
    }

    const auto first_validation = results.begin() + static_cast<std::ptrdiff_t>(ex.estimation.size());
    const SensitivityStudy study =
        make_sensitivity_study(problem, params, std::vector<WindowSensitivity>(results.begin(), first_validation),
                               std::vector<WindowSensitivity>(first_validation, results.end()));
    const std::vector<OutputRanking> rankings = rank_parameters(study);
    const SensitivityRunInfo run{TVID_VERSION, cmd.common.command_line, threads, seconds};
    write_sensitivity_report(dir, study, rankings, run);
    if (cmd.common.json) {
        std::cout << json_with_report(sensitivity_json(study, rankings, run), dir) << std::endl;
    } else if (!cmd.common.quiet) {
        std::cout << sensitivity_summary_text(study, rankings, run, dir.string()) << std::flush;
    }
    return kExitDone;
}

CommandRow sensitivity_command_row() {
    return {"sensitivity", "forward sensitivities dy/dp of the outputs to each free parameter, and their ranking", false,
            [](CLI::App& sub) -> CommandRunner {
                auto sensitivity = std::make_shared<SensitivityCommand>();
                add_common(sub, sensitivity->common);
                sub.add_option("--params", sensitivity->params_file,
                               "parameter file (default: the experiment's init values)");
                sub.add_option("-o,--output-dir,--output", sensitivity->output_dir,
                               "output directory (default: report.dir or results/NAME, then /sensitivity)")
                    ->check(kNonEmptyPath);
                sub.add_flag("--force", sensitivity->force, "replace files in the output directory that tvid did not write");
                sub.add_flag("--validation", sensitivity->validation, "include the validation windows");
                return [sensitivity](const CommandContext& context) {
                    sensitivity->common.command_line = context.command_line;
                    return run_sensitivity_command(*sensitivity);
                };
            }};
}

}  // namespace tvid::cli

// `tvid fit EXP.yaml`: identify the free parameters and write the report directory.

#include <chrono>
#include <cstdio>
#include <iostream>
#include <memory>

#include "command_options.hpp"
#include "command_table.hpp"
#include "commands.hpp"
#include "tvid/experiment/overrides.hpp"
#include "terminal.hpp"
#include "tvid/estimation/identification_problem.hpp"
#include "tvid/estimation/parallel_evaluator.hpp"
#include "tvid/experiment/experiment.hpp"
#include "tvid/fit/fit_run.hpp"
#include "tvid/fit/swarm_time_note.hpp"
#include "tvid/parallel/distributed_evaluator.hpp"
#include "tvid/parallel/on_every_process.hpp"
#include "tvid/report/report_directory.hpp"
#include "tvid/report/report_writer.hpp"
#include "tvid/util/input_error.hpp"
#include "tvid/util/stop_request.hpp"
#include "tvid/io/json_text.hpp"

namespace tvid::cli {


namespace {

// The experiment and its identification problem (which refers to the experiment).
struct LoadedFit {
    explicit LoadedFit(Experiment e) : experiment(std::move(e)), problem(experiment) {}
    Experiment experiment;
    IdentificationProblem problem;
    OutputDirectoryLock directory_lock;  ///< the root's claim on the report directory
};

}  // namespace

int run_fit_command(const FitCommand& cmd) {
    ProcessGroup alone;
    ProcessGroup& group = cmd.processes ? *cmd.processes : alone;
    std::vector<Override> overrides = parse_overrides(cmd.common.overrides);
    if (!cmd.optimizer.empty()) overrides.push_back(Override{"estimation.optimizer", cmd.optimizer});
    // Every process loads the experiment; the root also claims the report directory.
    const auto loaded = on_every_process(group, [&] {
        auto l = std::make_unique<LoadedFit>(load_experiment(cmd.common.experiment, overrides));
        if (l->problem.dimension() == 0)
            throw InputError(l->experiment.file.string(), 0, "parameters",
                             "every parameter is fixed: there is nothing to identify");
        // Before the fit: refuse early, not after it. The root holds the directory until
        // the report is written.
        if (group.is_root())
            l->directory_lock = prepare_report_directory(report_directory(l->experiment, cmd.output_dir), cmd.force, l->experiment.name);
        return l;
    });
    const Experiment& ex = loaded->experiment;
    const IdentificationProblem& problem = loaded->problem;
    if (!group.is_root()) {  // score the root's swarm candidates until it is done
        ParallelEvaluator local(problem, EvaluatorOptions(cmd.common.threads));
        serve_candidate_evaluations(group, local, problem.dimension());
        return kExitDone;
    }
    CandidateServers servers(group);  // released after the fit, or when anything below throws
    const std::filesystem::path dir = report_directory(ex, cmd.output_dir);

    FitOptions options;
    options.threads = cmd.common.threads;
    options.seed = cmd.seed;
    const int planned = planned_iterations(ex.estimation_settings);
    const bool planned_is_cap = planned_iterations_are_a_cap(ex.estimation_settings);
    ProgressLine progress(wants_progress_line(cmd.common.quiet, cmd.common.json), planned, planned_is_cap);
    const auto started = std::chrono::steady_clock::now();
    options.progress = [&](const HistoryRow& row) {
        // After the swarm's first iteration: how long the rest will take, before it runs.
        if (row.iteration == 0 && !cmd.common.quiet) {
            const double first = std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
            const std::string note = swarm_time_note(ex.estimation_settings, problem.dimension(), row.evaluations, first);
            if (!note.empty()) std::cerr << "tvid: " << note << std::endl;
        }
        progress.update(row);
        return true;
    };
    // Ctrl-C / SIGTERM from here on: stop the optimizer, keep its best point, write the report.
    install_stop_signal_handlers();
    options.stop = &stop_request();
    options.processes = &group;
    const FitResult fit = run_fit(problem, options);
    servers.release();
    progress.finish();

    const RunContext context{TVID_VERSION, cmd.common.command_line};
    write_fit_report(dir, problem, fit, context);
    if (cmd.common.json) {
        std::cout << json_with_report(fit_summary_json(problem, fit, context), dir) << std::endl;
    } else if (!cmd.common.quiet) {
        std::cout << fit_summary_text(problem, fit, dir.string()) << std::flush;
    }
    // The exit status agrees with summary.json's "interrupted": a stop that came after the
    // optimizer had finished left a complete fit.
    if (fit.interrupted) {
        if (!cmd.common.quiet)
            std::cerr << "tvid: interrupted; the report in " << dir.string() << " holds the best parameters so far\n";
        return kExitInterrupted;
    }
    if (stop_requested() && !cmd.common.quiet)
        std::cerr << "tvid: the stop request came after the fit had finished; the report in " << dir.string()
                  << " is complete\n";
    if (!fit.success) {
        // Why, where it shows at the init values (the parameters the report holds).
        const std::string at_init = first_failed_window(fit.evaluation);
        const std::string why = at_init.empty() ? "" : "at the init values, in " + at_init;
        std::cerr << (fit.run.termination_type == TerminationType::start_failed
                          ? "tvid: the simulation at the start failed (every candidate failed" + (why.empty() ? "" : "; " + why) + ")"
                          : "tvid: every candidate's simulation failed" + (why.empty() ? "" : " (" + why + ")"))
                  << "; the report in " << dir.string() << " says so\n";
        return kExitNotSucceeded;
    }
    if ((cmd.strict || ex.estimation_settings.strict) && fit.verdict.has_errors()) {
        const Finding& first = fit.verdict.findings.front();  // errors come first
        std::cerr << "tvid: " << (cmd.strict ? "--strict" : "estimation.strict") << ": the verdict has "
                  << fit.verdict.summary() << " (" << first.code << ": " << first.message << ")\n";
        return kExitNotSucceeded;
    }
    return kExitDone;
}

CommandRow fit_command_row() {
    return {"fit", "identify the free parameters and write a report directory", true, [](CLI::App& sub) -> CommandRunner {
        auto fit = std::make_shared<FitCommand>();
        add_common(sub, fit->common);
        sub.add_option("-o,--output-dir,--output", fit->output_dir, "report directory (default: report.dir or results/NAME)")
            ->check(kNonEmptyPath);
        sub.add_option("--seed", fit->seed, "random seed of the optimizer")->check(kSeed);
        std::vector<std::string> optimizers;
        for (const OptimizerKindRow& row : optimizer_kinds()) optimizers.emplace_back(row.name);
        sub.add_option("--optimizer", fit->optimizer, optimizer_names() + " (overrides estimation.optimizer)")
            ->check(CLI::IsMember(optimizers));  // the error names the flag the user typed
        sub.add_flag("--force", fit->force, "replace a report already in the report directory");
        sub.add_flag("--strict", fit->strict, "exit 1 when the verdict has an error (for CI)");
        return [fit](const CommandContext& context) {
            fit->common.command_line = context.command_line;
            fit->processes = context.processes;
            return run_fit_command(*fit);
        };
    }};
}

}  // namespace tvid::cli

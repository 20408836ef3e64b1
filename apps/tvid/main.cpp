// tvid: identify the physical parameters of powertrain torsional-vibration models.
// Exit status: the table kExitStatuses (commands.hpp), which every --help lists.

#include <CLI/CLI.hpp>
#include <algorithm>
#include <cctype>
#include <cmath>
#include <optional>
#include <iostream>
#include <iterator>
#include <vector>

#include "commands.hpp"
#include "tvid/estimation/parallel_evaluator.hpp"
#include "tvid/experiment/experiment.hpp"
#include "tvid/parallel/process_group.hpp"
#include "tvid/util/input_error.hpp"
#include "tvid/util/text.hpp"

namespace {

// "pso, lm, nlopt, pso+lm or multistart"
std::string optimizer_names() {
    std::string s;
    const auto& rows = tvid::optimizer_kinds();
    for (std::size_t i = 0; i < rows.size(); ++i) {
        if (i > 0) s += i + 1 == rows.size() ? " or " : ", ";
        s += rows[i].name;
    }
    return s;
}

std::string joined_command_line(int argc, char** argv) {
    std::string s;
    for (int i = 0; i < argc; ++i) {
        if (i) s += ' ';
        s += argv[i];
    }
    return s;
}

// A seed is a whole number from 0 to 2^64 - 1, written as such (CLI11 would wrap "-1").
const CLI::Validator kSeed(
    [](std::string& text) -> std::string {
        if (text.empty() || text.find_first_not_of("0123456789") != std::string::npos)
            return "a seed is a whole number from 0 to 18446744073709551615, not '" + text + "'";
        return {};
    },
    "SEED");

// A relative tolerance: a finite number >= 0 (CLI::NonNegativeNumber lets "nan" through).
const CLI::Validator kTolerance(
    [](std::string& text) -> std::string {
        double v = 0;
        if (!CLI::detail::lexical_cast(text, v) || !std::isfinite(v) || v < 0)
            return "a tolerance is a finite number >= 0, not '" + text + "'";
        return {};
    },
    "TOL");

// An output path given as -o must name something: "" is refused rather than falling back.
const CLI::Validator kNonEmptyPath(
    [](std::string& text) -> std::string { return text.empty() ? "the path is empty" : std::string(); }, "PATH");

// The exit statuses, for every --help.
std::string exit_status_help() {
    std::string s = "Exit status:";
    for (const tvid::cli::ExitStatusRow& row : tvid::cli::kExitStatuses)
        s += "\n  " + std::to_string(row.status) + (row.status < 10 ? "    " : "  ") + row.meaning;
    return s;
}

// "; did you mean 'simulate'?" for the command `word` most likely meant, else "": the one
// command it begins (sim), the command it spells in other case (FIT), else the nearest by
// edit distance when that is near.
std::string nearest_command_hint(const CLI::App& app, const std::string& word) {
    const auto lower = [](std::string text) {
        for (char& c : text) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
        return text;
    };
    const std::string folded = lower(word);
    std::vector<std::string> begun;
    for (const CLI::App* sub : app.get_subcommands({})) {
        const std::string name = sub->get_name();
        if (lower(name) == folded) return "; did you mean '" + name + "'?";
        if (!folded.empty() && name.rfind(folded, 0) == 0) begun.push_back(name);
    }
    if (begun.size() == 1) return "; did you mean '" + begun.front() + "'?";
    std::string nearest;
    std::size_t best = word.size();
    for (const CLI::App* sub : app.get_subcommands({})) {
        const std::size_t d = tvid::edit_distance(folded, sub->get_name());
        if (d < best) best = d, nearest = sub->get_name();
    }
    if (nearest.empty() || best > std::max<std::size_t>(2, word.size() / 3)) return "";
    return "; did you mean '" + nearest + "'?";
}

std::optional<std::string> unknown_command(const CLI::App& app, int argc, char** argv) {
    if (argc < 2 || argv[1][0] == '-') return std::nullopt;
    const std::string word = argv[1];
    for (const CLI::App* sub : app.get_subcommands({}))
        if (sub->get_name() == word) return std::nullopt;
    return "tvid: '" + word + "' is not a tvid command" + nearest_command_hint(app, word) + " (tvid --help lists them)";
}

void add_common(CLI::App* sub, tvid::cli::CommonOptions& o) {
    sub->add_option("experiment", o.experiment, "experiment file (YAML)")->required();
    sub->add_option("--set", o.overrides, "override a setting, e.g. --set estimation.pso.iterations=50")
        ->type_name("KEY=VALUE");
    sub->add_option("--threads", o.threads, "threads (default: all cores; at most " + std::to_string(tvid::kMaxThreads) + ")")
        ->check(CLI::Range(0, tvid::kMaxThreads));
    sub->add_flag("-q,--quiet", o.quiet, "print nothing but errors");
    sub->add_flag("--json", o.json, "print the summary as JSON on stdout");
}

// The one file simulate and validate write: -o FILE, or --output-dir DIR (its default
// name there), and --force.
void add_file_output(CLI::App* sub, tvid::cli::EvaluateCommand& cmd, const std::string& what,
                     const std::string& default_name) {
    auto* file = sub->add_option("-o,--output", cmd.output, "write " + what + " to this file")->check(kNonEmptyPath);
    sub->add_option("--output-dir", cmd.output_dir, "write " + default_name + " into this folder")
        ->check(kNonEmptyPath)
        ->excludes(file);
    sub->add_flag("--force", cmd.force, "replace a file that tvid did not write");
}

}  // namespace

int main(int argc, char** argv) {
    using namespace tvid::cli;
    // Under mpirun: fit and batch run on every process; the root alone prints and writes.
    tvid::ProcessGroup processes(argc, argv);
    if (!processes.is_root()) {
        std::cout.rdbuf(nullptr);
        std::cerr.rdbuf(nullptr);
    }
    // Named: the usage line says `tvid`, not the path the binary was started by.
    CLI::App app{"tvid: identify torsional-vibration model parameters of powertrains from measurements", "tvid"};
    app.set_version_flag("--version", std::string("tvid ") + TVID_VERSION);
    app.require_subcommand(1);

    FitCommand fit;
    auto* fit_cmd = app.add_subcommand("fit", "identify the free parameters and write a report directory");
    add_common(fit_cmd, fit.common);
    fit_cmd->add_option("-o,--output-dir,--output", fit.output_dir, "report directory (default: report.dir or results/NAME)")->check(kNonEmptyPath);
    fit_cmd->add_option("--seed", fit.seed, "random seed of the optimizer")->check(kSeed);
    std::vector<std::string> optimizers;
    for (const tvid::OptimizerKindRow& row : tvid::optimizer_kinds()) optimizers.emplace_back(row.name);
    fit_cmd->add_option("--optimizer", fit.optimizer, optimizer_names() + " (overrides estimation.optimizer)")
        ->check(CLI::IsMember(optimizers));  // the error names the flag the user typed
    fit_cmd->add_flag("--force", fit.force, "replace a report already in the report directory");
    fit_cmd->add_flag("--strict", fit.strict, "exit 1 when the verdict has an error (for CI)");

    EvaluateCommand simulate;
    auto* sim_cmd = app.add_subcommand("simulate", "simulate every window and print measured vs simulated as CSV");
    add_common(sim_cmd, simulate.common);
    sim_cmd->add_option("--params", simulate.params_file, "parameter file (params.json of a fit, or {name: value})");
    add_file_output(sim_cmd, simulate, "the CSV", "simulation.csv");

    EvaluateCommand validate;
    auto* val_cmd = app.add_subcommand("validate", "score a parameter set on the estimation and validation windows");
    add_common(val_cmd, validate.common);
    val_cmd->add_option("--params", validate.params_file, "parameter file")->required();
    add_file_output(val_cmd, validate, "the JSON", "validation.json");

    SensitivityCommand sensitivity;
    auto* sens_cmd = app.add_subcommand(
        "sensitivity", "forward sensitivities dy/dp of the outputs to each free parameter, and their ranking");
    add_common(sens_cmd, sensitivity.common);
    sens_cmd->add_option("--params", sensitivity.params_file, "parameter file (default: the experiment's init values)");
    sens_cmd->add_option("-o,--output-dir,--output", sensitivity.output_dir,
                         "output directory (default: report.dir or results/NAME, then /sensitivity)")
        ->check(kNonEmptyPath);
    sens_cmd->add_flag("--force", sensitivity.force, "replace files in the output directory that tvid did not write");
    sens_cmd->add_flag("--validation", sensitivity.validation, "include the validation windows");

    ProfileCommand profile;
    auto* profile_cmd = app.add_subcommand(
        "profile", "profile likelihood of one parameter: the others refitted on a grid of its values");
    add_common(profile_cmd, profile.common);
    profile_cmd->add_option("--param", profile.parameter, "the free parameter to profile")->required();
    profile_cmd->add_option("--points", profile.points, "grid points (default 21)")->check(CLI::Range(3, 1001));
    profile_cmd->add_option("--from", profile.from, "the grid's lower end (default: optimum - 4 standard errors)");
    profile_cmd->add_option("--to", profile.to, "the grid's upper end (default: optimum + 4 standard errors)");
    profile_cmd->add_option("--params", profile.params_file, "start of the fit to the optimum (default: the init values)");
    profile_cmd->add_option("-o,--output-dir,--output", profile.output_dir,
                            "output directory (default: report.dir or results/NAME, then /profile-PARAM)")
        ->check(kNonEmptyPath);
    profile_cmd->add_flag("--force", profile.force, "replace files in the output directory that tvid did not write");

    CheckCommand check;
    auto* check_cmd = app.add_subcommand("check", "compare a fit report with a reference of expected values (CI)");
    check_cmd->add_option("report", check.report_dir, "report directory written by tvid fit")->required();
    auto* reference_opt = check_cmd->add_option("--reference", check.reference, "reference file (JSON) to check against");
    auto* write_opt = check_cmd->add_option("--write-reference", check.write_reference,
                                            "write a reference from this known-good report instead");
    reference_opt->excludes(write_opt);
    check_cmd->add_option("--rel", check.rel,
                          "relative tolerance written: the default, and the least a parameter, the cost and Q "
                          "get (default 0.01)")
        ->needs(write_opt)
        ->check(kTolerance);
    check_cmd->add_option("--sigmas", check.sigmas,
                          "tolerance written for each parameter in its standard errors, and for the cost, Q and "
                          "the residual ratio in their spread over the noise (default 5)")
        ->needs(write_opt)
        ->check(kTolerance);
    check_cmd->add_flag("--force", check.force, "replace a --write-reference file that tvid did not write")
        ->needs(write_opt);
    check_cmd->add_flag("-q,--quiet", check.quiet, "print only the final line");
    check_cmd->add_flag("--json", check.json, "print the checks as JSON");

    BatchCommand batch;
    auto* batch_cmd = app.add_subcommand("batch", "fit the experiment to many recordings and/or cycles, one row per job");
    add_common(batch_cmd, batch.common);
    batch_cmd->add_option("-o,--output-dir,--output", batch.output_dir, "output directory (default: the report directory + -batch)")->check(kNonEmptyPath);
    batch_cmd->add_option("--seed", batch.seed, "random seed of the optimizer, the same for every job")->check(kSeed);
    batch_cmd->add_option("--data", batch.data_globs, "recordings: files, or globs such as 'recordings/*.csv'");
    batch_cmd->add_option("--data-list", batch.data_list, "file with one recording per line (relative to it)");
    batch_cmd->add_option("--cycles", batch.cycles, "fit each cycle on its own: 3-9 or 3,5,7");
    batch_cmd->add_flag("--no-validation", batch.no_validation, "no validation (else the next cycle validates)");
    auto* resume_flag = batch_cmd->add_flag("--resume", batch.resume, "continue an interrupted batch: skip the jobs in batch.csv");
    batch_cmd->add_flag("--force", batch.force, "replace an existing batch.csv")->excludes(resume_flag);
    batch_cmd->add_flag("--strict", batch.strict, "exit 1 when a job's verdict has an error (for CI)");
    batch_cmd->add_flag("--cross", batch.cross, "validate each job's parameters on every job's data (matrix.csv)");

    ModesCommand modes;
    auto* modes_cmd = app.add_subcommand("modes", "torsional modes of the model linearised at an estimation window's start");
    FrfCommand frf;
    auto* frf_cmd = app.add_subcommand("frf", "the model's frequency response from an input to an output, beside the measured H1");
    for (auto [sub, o] : {std::pair{modes_cmd, &modes}, std::pair{frf_cmd, &frf.modes}}) {
        add_common(sub, o->common);
        sub->add_option("--params", o->params_file, "parameter file (default: the experiment's init values)");
        sub->add_option("-o,--output-dir", o->output_dir,
                        std::string("output directory (default: report.dir or results/NAME, then /") +
                            (sub == modes_cmd ? "modes)" : "frf)"))
            ->check(kNonEmptyPath);
        sub->add_flag("--force", o->force, "replace files in the output directory that tvid did not write");
        sub->add_option("--window", o->window, "the estimation window (0, 1, ...) whose start is the operating point");
        sub->add_option("--angles", o->angle_dependence,
                        "angle-dependent elements (cylinders, order torques): revolution_mean (default) or operating_point")
            ->check(CLI::IsMember({"revolution_mean", "operating_point"}));
    }
    frf_cmd->add_option("--input", frf.input, "the model input (or its CSV column)")->required();
    frf_cmd->add_option("--output", frf.output, "the measured output (or its CSV column)")->required();
    auto* segment_option = frf_cmd->add_option("--segment", frf.segment,
                                               "Welch's segment in samples (default: from the window lengths)")
                               ->check(CLI::Range(std::size_t{8}, std::size_t{1} << 30));
    frf_cmd->add_option("--resolution", frf.resolution_hz,
                        "the frequency resolution in Hz: the segment is fs/HZ samples, rounded up")
        ->check(CLI::PositiveNumber)
        ->excludes(segment_option);

    bool models_json = false;
    auto* models_cmd = app.add_subcommand("models", "list the preset models with their parameters, inputs, outputs");
    models_cmd->add_flag("--json", models_json, "as JSON");

    std::string help_topic;
    auto* help_cmd = app.add_subcommand("help", "tvid help COMMAND: the options of one command");
    help_cmd->add_option("command", help_topic, "the command");

    const std::string footer = exit_status_help();
    app.footer(footer);
    for (CLI::App* sub : app.get_subcommands({})) sub->footer(footer);
    if (const auto unknown = unknown_command(app, argc, argv)) {
        std::cerr << *unknown << '\n';
        return tvid::cli::kExitBadInput;
    }

    try {
        app.parse(argc, argv);
    } catch (const CLI::ParseError& e) {
        if (e.get_exit_code() == 0) return app.exit(e);  // --help, --version
        // One line, as every other input error: CLI11's own adds "Run with --help".
        std::cerr << "tvid: " << e.what() << " (tvid " << (app.get_subcommands().empty() ? "" : app.get_subcommands().front()->get_name() + " ")
                  << "--help)\n";
        return kExitBadInput;
    }
    if (*help_cmd) {
        if (help_topic.empty()) {  // the command list (app.help() would show the selected `help` itself)
            std::cout << app.get_formatter()->make_help(&app, app.get_name(), CLI::AppFormatMode::Normal);
            return kExitDone;
        }
        for (const CLI::App* sub : app.get_subcommands({}))
            if (sub->get_name() == help_topic) {
                std::cout << sub->help();
                return kExitDone;
            }
        std::cerr << "tvid help: '" << help_topic << "' is not a tvid command" << nearest_command_hint(app, help_topic)
                  << " (tvid --help lists them)\n";
        return kExitBadInput;
    }
    const std::string command_line = joined_command_line(argc, argv);
    fit.common.command_line = simulate.common.command_line = validate.common.command_line =
        sensitivity.common.command_line = profile.common.command_line = command_line;
    modes.common.command_line = frf.modes.common.command_line = command_line;

    batch.common.command_line = command_line;
    fit.processes = batch.processes = &processes;

    try {
        if (*batch_cmd) return run_batch_command(batch);
        if (*fit_cmd) return run_fit_command(fit);
        if (!processes.is_root()) return kExitDone;  // the other commands run on the root alone
        if (*sim_cmd) return run_simulate_command(simulate);
        if (*val_cmd) return run_validate_command(validate);
        if (*sens_cmd) return run_sensitivity_command(sensitivity);
        if (*profile_cmd) return run_profile_command(profile);
        if (*models_cmd) return run_models_command(models_json);
        if (*check_cmd) return run_check_command(check);
        if (*modes_cmd) return run_modes_command(modes);
        if (*frf_cmd) return run_frf_command(frf);
    } catch (const tvid::InputError& e) {
        std::cerr << e.what() << '\n';
        return kExitBadInput;
    } catch (const std::exception& e) {
        std::cerr << "tvid: " << e.what() << '\n';
        return kExitBadInput;
    }
    return kExitBadInput;
}

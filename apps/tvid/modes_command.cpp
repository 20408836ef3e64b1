// `tvid modes EXP.yaml`: the torsional modes of the model linearised at an estimation
// window's start; `tvid frf EXP.yaml --input IN --output OUT`: its frequency response
// beside the measured H1 of the same channels.

#include <iostream>

#include <memory>

#include "command_options.hpp"
#include "command_table.hpp"
#include "commands.hpp"
#include "terminal.hpp"
#include "tvid/report/report_directory.hpp"
#include "tvid/experiment/overrides.hpp"
#include "tvid/analysis/frf_comparison.hpp"
#include "tvid/analysis/torsional_modes.hpp"
#include "tvid/experiment/experiment.hpp"
#include "tvid/io/json_text.hpp"
#include "tvid/io/output_directory.hpp"
#include "tvid/report/modes_report.hpp"
#include "tvid/report/parameter_file.hpp"
#include "tvid/util/input_error.hpp"

namespace tvid::cli {


namespace {

// What both commands need: the experiment, its problem, the parameters and the window.
struct LinearisationSetup {
    Experiment ex;
    std::vector<double> params;
    std::size_t window = 0;
    AngleDependence angles = AngleDependence::revolution_mean;
};

LinearisationSetup prepare_linearisation(const ModesCommand& cmd) {
    LinearisationSetup s{load_experiment(cmd.common.experiment, parse_overrides(cmd.common.overrides)), {}, 0, {}};
    const std::size_t windows = s.ex.estimation.size();
    if (cmd.window < 0 || static_cast<std::size_t>(cmd.window) >= windows)
        throw InputError("", 0, "--window",
                         std::to_string(cmd.window) + " is no estimation window of " + s.ex.file.string() + ": it has " +
                             std::to_string(windows) + " (0 to " + std::to_string(windows - 1) + ")");
    s.window = static_cast<std::size_t>(cmd.window);
    s.angles = cmd.angle_dependence == "operating_point" ? AngleDependence::operating_point : AngleDependence::revolution_mean;
    s.params = cmd.params_file.empty() ? initial_parameters(s.ex) : read_parameter_file(cmd.params_file, s.ex);
    return s;
}

ModesRunInfo run_info(const Experiment& ex, const CommonOptions& common) {
    return ModesRunInfo{TVID_VERSION, common.command_line, ex.name, ex.network.preset};
}

// The index in `names` of `name`, or of the channel bound to column `name`; -1 if neither.
int find_channel(const std::vector<std::string>& names, const std::vector<ChannelBinding>& bindings, const std::string& name) {
    for (std::size_t i = 0; i < names.size(); ++i)
        if (names[i] == name) return static_cast<int>(i);
    for (const ChannelBinding& b : bindings)
        if (b.column == name)
            for (std::size_t i = 0; i < names.size(); ++i)
                if (names[i] == b.model_name) return static_cast<int>(i);
    return -1;
}

std::string listed(const std::vector<std::string>& names) {
    std::string s;
    for (const std::string& n : names) s += (s.empty() ? "" : ", ") + n;
    return s.empty() ? "none" : s;
}

}  // namespace

int run_modes_command(const ModesCommand& cmd) {
    const LinearisationSetup s = prepare_linearisation(cmd);
    const std::filesystem::path dir =
        cmd.output_dir.empty() ? report_directory(s.ex, "") / "modes" : std::filesystem::path(cmd.output_dir);
    const OutputDirectoryLock lock = prepare_output_directory(dir, "modes directory", {"modes.csv", "modes.json"}, "modes.json", cmd.force);
    const IdentificationProblem problem(s.ex);
    ModesStudy study;
    try {
        study = study_modes(problem, s.params, s.window, s.angles);
    } catch (const std::runtime_error& e) {
        std::cerr << "tvid: no linearisation: " << e.what() << "; nothing written\n";
        return kExitNotSucceeded;
    }
    const ModesRunInfo run = run_info(s.ex, cmd.common);
    write_modes_report(dir, study, run);
    if (cmd.common.json)
        std::cout << json_with_report(modes_json(study, run), dir) << std::endl;
    else if (!cmd.common.quiet)
        std::cout << modes_table_text(study) << "report: " << dir.string() << "\n" << std::flush;
    return kExitDone;
}

int run_frf_command(const FrfCommand& cmd) {
    const LinearisationSetup s = prepare_linearisation(cmd.modes);
    const NetworkSpec& net = s.ex.network;
    const int input = find_channel(net.input_names, s.ex.inputs, cmd.input);
    if (input < 0)
        throw InputError("", 0, "--input",
                         "'" + cmd.input + "' is no input of the model by time; its inputs: " + listed(net.input_names));
    std::vector<std::string> measured;
    for (const int k : s.ex.output_indices) measured.push_back(net.outputs[static_cast<std::size_t>(k)].name);
    const int m = find_channel(measured, s.ex.outputs, cmd.output);
    if (m < 0)
        throw InputError("", 0, "--output",
                         "'" + cmd.output + "' is no measured output of the experiment; its outputs: " + listed(measured));
    const std::size_t output = static_cast<std::size_t>(s.ex.output_indices[static_cast<std::size_t>(m)]);
    const std::filesystem::path dir =
        cmd.modes.output_dir.empty() ? report_directory(s.ex, "") / "frf" : std::filesystem::path(cmd.modes.output_dir);
    const OutputDirectoryLock lock = prepare_output_directory(dir, "frf directory", {"frf.csv", "frf.json"}, "frf.json", cmd.modes.force);
    const IdentificationProblem problem(s.ex);
    FrfComparison frf;
    try {
        frf = compare_frf(problem, s.params, static_cast<std::size_t>(input), output, s.window, s.angles,
                          SpectralResolution{cmd.segment, cmd.resolution_hz});
    } catch (const std::invalid_argument& e) {
        throw InputError("", 0, cmd.segment > 0 ? "--segment" : "--resolution", e.what());
    } catch (const std::runtime_error& e) {
        std::cerr << "tvid: no frequency response: " << e.what() << "; nothing written\n";
        return kExitNotSucceeded;
    }
    const ModesRunInfo run = run_info(s.ex, cmd.modes.common);
    write_frf_report(dir, frf, run);
    if (cmd.modes.common.json)
        std::cout << json_with_report(frf_json(frf, run), dir) << std::endl;
    else if (!cmd.modes.common.quiet)
        std::cout << frf_summary_text(frf) << "report: " << dir.string() << "\n" << std::flush;
    return kExitDone;
}

// The options of modes and frf: the operating point and where the files go.
static void add_linearised_options(CLI::App& sub, ModesCommand& o, const std::string& folder) {
    add_common(sub, o.common);
    sub.add_option("--params", o.params_file, "parameter file (default: the experiment's init values)");
    sub.add_option("-o,--output-dir", o.output_dir,
                   "output directory (default: report.dir or results/NAME, then /" + folder + ")")
        ->check(kNonEmptyPath);
    sub.add_flag("--force", o.force, "replace files in the output directory that tvid did not write");
    sub.add_option("--window", o.window, "the estimation window (0, 1, ...) whose start is the operating point");
    sub.add_option("--angles", o.angle_dependence,
                   "angle-dependent elements (cylinders, order torques): revolution_mean (default) or operating_point")
        ->check(CLI::IsMember({"revolution_mean", "operating_point"}));
}

CommandRow modes_command_row() {
    return {"modes", "torsional modes of the model linearised at an estimation window's start", false,
            [](CLI::App& sub) -> CommandRunner {
                auto modes = std::make_shared<ModesCommand>();
                add_linearised_options(sub, *modes, "modes");
                return [modes](const CommandContext& context) {
                    modes->common.command_line = context.command_line;
                    return run_modes_command(*modes);
                };
            }};
}

CommandRow frf_command_row() {
    return {"frf", "the model's frequency response from an input to an output, beside the measured H1", false,
            [](CLI::App& sub) -> CommandRunner {
                auto frf = std::make_shared<FrfCommand>();
                add_linearised_options(sub, frf->modes, "frf");
                sub.add_option("--input", frf->input, "the model input (or its CSV column)")->required();
                sub.add_option("--output", frf->output, "the measured output (or its CSV column)")->required();
                auto* segment = sub.add_option("--segment", frf->segment,
                                               "Welch's segment in samples (default: from the window lengths)")
                                    ->check(CLI::Range(std::size_t{8}, std::size_t{1} << 30));
                sub.add_option("--resolution", frf->resolution_hz,
                               "the frequency resolution in Hz: the segment is fs/HZ samples, rounded up")
                    ->check(CLI::PositiveNumber)
                    ->excludes(segment);
                return [frf](const CommandContext& context) {
                    frf->modes.common.command_line = context.command_line;
                    return run_frf_command(*frf);
                };
            }};
}

}  // namespace tvid::cli

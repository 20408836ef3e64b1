// `tvid profile EXP.yaml --param NAME`: the profile likelihood of one parameter, its 95 %
// interval read where Δχ² crosses 3.84, next to the linearised one.

#include <cmath>
#include <cstdio>
#include <iostream>

#include <memory>

#include "command_options.hpp"
#include "command_table.hpp"
#include "commands.hpp"
#include "terminal.hpp"
#include "tvid/report/report_directory.hpp"
#include "tvid/experiment/overrides.hpp"
#include "tvid/experiment/experiment.hpp"
#include "tvid/fit/profile_likelihood.hpp"
#include "tvid/io/json_text.hpp"
#include "tvid/io/output_directory.hpp"
#include "tvid/report/parameter_file.hpp"
#include "tvid/report/profile_report.hpp"
#include "tvid/util/stop_request.hpp"

namespace tvid::cli {


namespace {


std::string profile_text(const ProfileResult& p, const std::string& dir) {
    std::string out;
    char line[256];
    std::snprintf(line, sizeof line, "tvid profile %s: %zu points, %.2f s on %d thread%s\n", p.parameter.c_str(),
                  p.points.size(), p.seconds, p.threads, p.threads == 1 ? "" : "s");
    out += line;
    std::snprintf(line, sizeof line, "  optimum %s = %.8g, cost %.8g (%s), s2 %.4g over %zu residuals\n",
                  p.parameter.c_str(), p.best_value, p.best_cost, p.optimum_termination.c_str(), p.s2, p.residuals);
    out += line;
    out += "    value            delta chi2   converged\n";
    for (const ProfilePoint& q : p.points) {
        std::snprintf(line, sizeof line, "    %-16.8g %-12.4g %s\n", q.value, q.delta_chi2, q.converged ? "yes" : q.termination.c_str());
        out += line;
    }
    // An open side: still below the threshold at the grid's end.
    const auto end = [](const std::optional<double>& v, double grid_end) {
        char buf[64];
        if (v) std::snprintf(buf, sizeof buf, "%.6g", *v);
        else std::snprintf(buf, sizeof buf, "open (below the threshold at %.6g)", grid_end);
        return std::string(buf);
    };
    out += "  95 % profile interval [" + end(p.low, p.points.front().value) + ", " + end(p.high, p.points.back().value) + "]";
    if (std::isfinite(p.std_error)) {
        std::snprintf(line, sizeof line, "; linearised [%.6g, %.6g]", p.best_value - 1.959963984540054 * p.std_error,
                      p.best_value + 1.959963984540054 * p.std_error);
        out += line;
    }
    out += "\n";
    if (p.disconnected)
        out += "  warning: the values below the threshold form more than one valley (another local optimum): the "
               "interval is their hull\n";
    if (p.better_point_found)
        out += "  warning: a grid point has a lower cost than the optimum: the fit to it stopped early; profile again "
               "from that point (--params)\n";
    out += "  report: " + dir + "\n";
    return out;
}

}  // namespace

int run_profile_command(const ProfileCommand& cmd) {
    const Experiment ex = load_experiment(cmd.common.experiment, parse_overrides(cmd.common.overrides));
    const std::vector<double> start = cmd.params_file.empty() ? initial_parameters(ex) : read_parameter_file(cmd.params_file, ex);
    ProfileOptions options;
    options.parameter = cmd.parameter;
    options.points = cmd.points;
    options.from = cmd.from;
    options.to = cmd.to;
    options.threads = cmd.common.threads;
    install_stop_signal_handlers();
    options.stop = &stop_request();
    // The parameter is checked before the directory is named after it and claimed: only a
    // parameter of the experiment (a plain name, experiment/parameter_reader.cpp) names it.
    check_profile_request(ex, options);
    const std::filesystem::path dir = cmd.output_dir.empty()
                                          ? report_directory(ex, "") / ("profile-" + cmd.parameter)
                                          : std::filesystem::path(cmd.output_dir);
    const OutputDirectoryLock lock = prepare_output_directory(dir, "profile directory", {"profile.csv", "profile.json"}, "profile.json", cmd.force);
    const ProfileResult profile = profile_likelihood(ex, start, options);
    if (stop_requested()) {
        std::cerr << "tvid: interrupted; no profile written\n";
        return kExitInterrupted;
    }
    const ProfileRunInfo run{TVID_VERSION, cmd.common.command_line, ex.name};
    write_profile_report(dir, profile, run);
    if (cmd.common.json) std::cout << json_with_report(profile_json(profile, run), dir) << std::endl;
    else if (!cmd.common.quiet) std::cout << profile_text(profile, dir.string()) << std::flush;
    return kExitDone;
}

CommandRow profile_command_row() {
    return {"profile", "profile likelihood of one parameter: the others refitted on a grid of its values", false,
            [](CLI::App& sub) -> CommandRunner {
                auto profile = std::make_shared<ProfileCommand>();
                add_common(sub, profile->common);
                sub.add_option("--param", profile->parameter, "the free parameter to profile")->required();
                sub.add_option("--points", profile->points, "grid points (default 21)")->check(CLI::Range(3, 1001));
                sub.add_option("--from", profile->from, "the grid's lower end (default: optimum - 4 standard errors)");
                sub.add_option("--to", profile->to, "the grid's upper end (default: optimum + 4 standard errors)");
                sub.add_option("--params", profile->params_file,
                               "start of the fit to the optimum (default: the init values)");
                sub.add_option("-o,--output-dir,--output", profile->output_dir,
                               "output directory (default: report.dir or results/NAME, then /profile-PARAM)")
                    ->check(kNonEmptyPath);
                sub.add_flag("--force", profile->force, "replace files in the output directory that tvid did not write");
                return [profile](const CommandContext& context) {
                    profile->common.command_line = context.command_line;
                    return run_profile_command(*profile);
                };
            }};
}

}  // namespace tvid::cli

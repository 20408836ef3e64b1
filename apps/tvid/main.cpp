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

#include "command_table.hpp"
#include "commands.hpp"
#include "tvid/estimation/parallel_evaluator.hpp"
#include "tvid/experiment/experiment.hpp"
#include "tvid/parallel/process_group.hpp"
#include "tvid/util/input_error.hpp"
#include "tvid/util/text.hpp"

namespace {

std::string joined_command_line(int argc, char** argv) {
    std::string s;
    for (int i = 0; i < argc; ++i) {
        if (i) s += ' ';
        s += argv[i];
    }
    return s;
}

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

// `tvid help [COMMAND]`: the command list, or one command's options.
int run_help(const CLI::App& app, const std::string& topic) {
    if (topic.empty()) {  // the command list (app.help() would show the selected `help` itself)
        std::cout << app.get_formatter()->make_help(&app, app.get_name(), CLI::AppFormatMode::Normal);
        return tvid::cli::kExitDone;
    }
    for (const CLI::App* sub : app.get_subcommands({}))
        if (sub->get_name() == topic) {
            std::cout << sub->help();
            return tvid::cli::kExitDone;
        }
    std::cerr << "tvid help: '" << topic << "' is not a tvid command" << nearest_command_hint(app, topic)
              << " (tvid --help lists them)\n";
    return tvid::cli::kExitBadInput;
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
    // One subcommand per row of the command table (command_table.hpp), and `help`.
    std::vector<std::pair<const CLI::App*, CommandRunner>> runners;
    for (const CommandRow& row : command_table()) {
        CLI::App* sub = app.add_subcommand(row.name, row.summary);
        runners.emplace_back(sub, row.define(*sub));
    }
    std::string help_topic;
    auto* help_cmd = app.add_subcommand("help", "tvid help COMMAND: the options of one command");
    help_cmd->add_option("command", help_topic, "the command");

    const std::string footer = exit_status_help();
    app.footer(footer);
    for (CLI::App* sub : app.get_subcommands({})) sub->footer(footer);
    if (const auto unknown = unknown_command(app, argc, argv)) {
        std::cerr << *unknown << '\n';
        return kExitBadInput;
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
    if (*help_cmd) return run_help(app, help_topic);
    const CommandContext context{joined_command_line(argc, argv), &processes};
    try {
        for (std::size_t k = 0; k < runners.size(); ++k) {
            if (!*runners[k].first) continue;
            // The commands other than fit and batch run on the root alone.
            if (!command_table()[k].on_every_process && !processes.is_root()) return kExitDone;
            return runners[k].second(context);
        }
    } catch (const tvid::InputError& e) {
        std::cerr << e.what() << '\n';
        return kExitBadInput;
    } catch (const std::exception& e) {
        std::cerr << "tvid: " << e.what() << '\n';
        return kExitBadInput;
    }
    return kExitBadInput;
}

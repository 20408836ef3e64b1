#pragma once
// The table of `tvid`'s commands, as elements and optimizers have theirs: each command's
// file defines its row (name, one-line summary, where it runs, and how it registers its
// options and runner), and main() adds a subcommand per row and runs the one chosen.
// Adding a command: its file with a XXX_command_row(), declared here, and one line in
// command_table.cpp.

#include <CLI/CLI.hpp>
#include <functional>
#include <string>
#include <vector>

namespace tvid {
class ProcessGroup;
}

namespace tvid::cli {

/// What every command's run is told: the command line as typed (for the reports) and the
/// processes under mpirun.
struct CommandContext {
    std::string command_line;
    ProcessGroup* processes = nullptr;
};

/// A command's run, with the options its registration bound; returns the exit status.
using CommandRunner = std::function<int(const CommandContext&)>;

struct CommandRow {
    const char* name;
    const char* summary;
    /// Under mpirun: true for a command every process runs (fit, batch); the others run on
    /// the root alone.
    bool on_every_process = false;
    /// Adds the command's options to its subcommand and returns its runner, which owns the
    /// values the options write to.
    std::function<CommandRunner(CLI::App& sub)> define;
};

CommandRow fit_command_row();
CommandRow simulate_command_row();
CommandRow validate_command_row();
CommandRow sensitivity_command_row();
CommandRow design_command_row();
CommandRow profile_command_row();
CommandRow check_command_row();
CommandRow batch_command_row();
CommandRow modes_command_row();
CommandRow frf_command_row();
CommandRow models_command_row();

/// Every command, in the order `tvid --help` lists them (`help` itself is main's).
const std::vector<CommandRow>& command_table();

}  // namespace tvid::cli

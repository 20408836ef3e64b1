#pragma once
// The subcommands of `tvid`. Each returns the process exit status of kExitStatuses.

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "tvid/check/reference_check.hpp"

namespace tvid {
class ProcessGroup;
}

namespace tvid::cli {

/// The exit status of every command, one table: the help text lists it, the commands
/// return its names.
inline constexpr int kExitDone = 0;
inline constexpr int kExitNotSucceeded = 1;
inline constexpr int kExitBadInput = 2;
inline constexpr int kExitInterrupted = 130;  // 128 + SIGINT, what shells report for Ctrl-C
struct ExitStatusRow {
    int status;
    const char* meaning;
};
inline constexpr ExitStatusRow kExitStatuses[] = {
    {kExitDone, "done"},
    {kExitNotSucceeded, "ran but did not succeed: every candidate failed, a check failed, or --strict and the verdict has an error"},
    {kExitBadInput, "bad input, told in one line FILE:LINE: key: what is wrong; nothing was written"},
    {kExitInterrupted, "interrupted by Ctrl-C or SIGTERM: a fit's report holds the best parameters so far"},
};

struct CommonOptions {
    std::string experiment;             ///< EXP.yaml
    std::vector<std::string> overrides; ///< --set key=value
    int threads = 0;
    bool quiet = false;
    bool json = false;                  ///< summary as JSON on stdout
    std::string command_line;
};

struct FitCommand {
    CommonOptions common;
    std::string output_dir;             ///< -o DIR (overrides report.dir)
    std::optional<std::uint64_t> seed;
    std::string optimizer;              ///< --optimizer NAME (overrides estimation.optimizer)
    bool force = false;                 ///< --force: replace a report already in the directory
    bool strict = false;                ///< --strict: exit 1 when the verdict has an error
    ProcessGroup* processes = nullptr;  ///< mpirun: every process runs the command (nullptr: this one)
};

struct EvaluateCommand {
    CommonOptions common;
    std::string params_file;            ///< --params P.json (empty: the experiment's init values)
    std::string output;                 ///< -o FILE.csv (simulate) / FILE.json (validate)
    std::string output_dir;             ///< --output-dir DIR: the file under its default name there
    bool force = false;                 ///< --force: replace a file there that tvid did not write
};

struct SensitivityCommand {
    CommonOptions common;
    std::string params_file;            ///< --params P.json (empty: the experiment's init values)
    std::string output_dir;             ///< -o DIR (default: the report directory + /sensitivity)
    bool force = false;                 ///< --force: replace files there that tvid did not write
    bool validation = false;            ///< --validation: the validation windows too
};

struct ProfileCommand {
    CommonOptions common;
    std::string parameter;              ///< --param NAME
    int points = 21;                    ///< --points N
    std::optional<double> from, to;     ///< --from, --to: the grid's ends
    std::string params_file;            ///< --params P.json: where the fit to the optimum starts
    std::string output_dir;             ///< -o DIR (default: the report directory + /profile-NAME)
    bool force = false;                 ///< --force: replace files there that tvid did not write
};
int run_profile_command(const ProfileCommand& cmd);

struct CheckCommand {
    std::string report_dir;             ///< REPORT_DIR written by `tvid fit`
    std::string reference;              ///< --reference REF.json
    std::string write_reference;        ///< --write-reference REF.json: make a reference instead
    double rel = 0.01;                  ///< --rel: the default relative tolerance written, and the floor
    double sigmas = kReferenceStandardErrors;  ///< --sigmas: tolerances in standard errors and spreads
    bool quiet = false;                 ///< only the final line
    bool json = false;                  ///< the rows as JSON
    bool force = false;                 ///< --force: replace a --write-reference file tvid did not write
};

// `tvid design`: a designed input and the predicted standard errors of candidate inputs (design/).
struct DesignCommand {
    CommonOptions common;
    bool evaluate = false;              ///< --evaluate: only predict for given and reference inputs, no design
    std::string input_file;             ///< --input FILE.csv: a given input to evaluate
    std::string column;                 ///< --column NAME: its column (default: the experiment's)
    std::string params_file;            ///< --params P.json (empty: the experiment's init values)
    std::string output_dir;             ///< -o DIR (default: the report directory + /design)
    bool force = false;                 ///< --force: replace files there that tvid did not write
};
int run_design_command(const DesignCommand& cmd);

int run_fit_command(const FitCommand& cmd);
int run_simulate_command(const EvaluateCommand& cmd);
int run_validate_command(const EvaluateCommand& cmd);
int run_sensitivity_command(const SensitivityCommand& cmd);
int run_models_command(bool json);
int run_check_command(const CheckCommand& cmd);

// `tvid batch`: many recordings and/or cycles of one experiment, one row per job.
struct BatchCommand {
    CommonOptions common;
    std::string output_dir;                 ///< -o DIR (default: the report directory + "-batch")
    std::optional<std::uint64_t> seed;
    std::vector<std::string> data_globs;    ///< --data 'recordings/*.csv' (repeatable)
    std::string data_list;                  ///< --data-list FILE: one CSV per line
    std::string cycles;                     ///< --cycles 3-9 or 3,5,7
    bool no_validation = false;             ///< --no-validation
    bool resume = false;                    ///< --resume: skip jobs already in batch.csv
    bool force = false;                     ///< --force: replace an existing batch.csv
    bool strict = false;                    ///< --strict: exit 1 when a job's verdict has an error
    bool cross = false;                     ///< --cross: each job's parameters validated on every job's data
    ProcessGroup* processes = nullptr;      ///< mpirun: every process runs the command (nullptr: this one)
};
int run_batch_command(const BatchCommand& cmd);

}  // namespace tvid::cli

namespace tvid::cli {

// `tvid modes` and `tvid frf`: the model linearised at an estimation window's start.
struct ModesCommand {
    CommonOptions common;
    std::string params_file;            ///< --params P.json (empty: the experiment's init values)
    std::string output_dir;             ///< -o DIR (default: the report directory + /modes)
    bool force = false;                 ///< --force: replace files there that tvid did not write
    int window = 0;                     ///< --window N: the estimation window whose start is the operating point
    std::string angle_dependence = "revolution_mean";  ///< --angles revolution_mean|operating_point
};
int run_modes_command(const ModesCommand& cmd);

struct FrfCommand {
    ModesCommand modes;                 ///< the same options; -o default: the report directory + /frf
    std::string input;                  ///< --input NAME: a model input (or its CSV column)
    std::string output;                 ///< --output NAME: a measured output (or its CSV column)
    std::size_t segment = 0;            ///< --segment N: Welch's segment in samples (0: the default rule)
    double resolution_hz = 0.0;         ///< --resolution HZ: the frequency resolution asked (0: the default rule)
};
int run_frf_command(const FrfCommand& cmd);

}  // namespace tvid::cli

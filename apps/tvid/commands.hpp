#pragma once
// The subcommands of `tvid`. Each returns the process exit status:
// 0 done, 1 ran but did not succeed (e.g. every candidate failed), 2 bad input.

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace tvid::cli {

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
};

struct EvaluateCommand {
    CommonOptions common;
    std::string params_file;            ///< --params P.json (empty: the experiment's init values)
    std::string output;                 ///< -o FILE.csv (simulate) / FILE.json (validate)
};

struct SensitivityCommand {
    CommonOptions common;
    std::string params_file;            ///< --params P.json (empty: the experiment's init values)
    std::string output_dir;             ///< -o DIR (default: the report directory + /sensitivity)
    bool validation = false;            ///< --validation: the validation windows too
};

int run_fit_command(const FitCommand& cmd);
int run_simulate_command(const EvaluateCommand& cmd);
int run_validate_command(const EvaluateCommand& cmd);
int run_sensitivity_command(const SensitivityCommand& cmd);
int run_models_command(bool json);

}  // namespace tvid::cli

#include "command_options.hpp"

#include <cmath>

#include "tvid/estimation/parallel_evaluator.hpp"
#include "tvid/experiment/experiment.hpp"

namespace tvid::cli {

const CLI::Validator kSeed(
    [](std::string& text) -> std::string {
        if (text.empty() || text.find_first_not_of("0123456789") != std::string::npos)
            return "a seed is a whole number from 0 to 18446744073709551615, not '" + text + "'";
        return {};
    },
    "SEED");

const CLI::Validator kTolerance(
    [](std::string& text) -> std::string {
        double v = 0;
        if (!CLI::detail::lexical_cast(text, v) || !std::isfinite(v) || v < 0)
            return "a tolerance is a finite number >= 0, not '" + text + "'";
        return {};
    },
    "TOL");

const CLI::Validator kNonEmptyPath(
    [](std::string& text) -> std::string { return text.empty() ? "the path is empty" : std::string(); }, "PATH");

void add_common(CLI::App& sub, CommonOptions& o) {
    sub.add_option("experiment", o.experiment, "experiment file (YAML)")->required();
    sub.add_option("--set", o.overrides, "override a setting, e.g. --set estimation.pso.iterations=50")
        ->type_name("KEY=VALUE");
    sub.add_option("--threads", o.threads, "threads (default: all cores; at most " + std::to_string(kMaxThreads) + ")")
        ->check(CLI::Range(0, kMaxThreads));
    sub.add_flag("-q,--quiet", o.quiet, "print nothing but errors");
    sub.add_flag("--json", o.json, "print the summary as JSON on stdout");
}

void add_file_output(CLI::App& sub, EvaluateCommand& cmd, const std::string& what, const std::string& default_name) {
    auto* file = sub.add_option("-o,--output", cmd.output, "write " + what + " to this file")->check(kNonEmptyPath);
    sub.add_option("--output-dir", cmd.output_dir, "write " + default_name + " into this folder")
        ->check(kNonEmptyPath)
        ->excludes(file);
    sub.add_flag("--force", cmd.force, "replace a file that tvid did not write");
}

std::string optimizer_names() {
    std::string s;
    const auto& rows = optimizer_kinds();
    for (std::size_t i = 0; i < rows.size(); ++i) {
        if (i > 0) s += i + 1 == rows.size() ? " or " : ", ";
        s += rows[i].name;
    }
    return s;
}

}  // namespace tvid::cli

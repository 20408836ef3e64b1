#pragma once
// The options that several commands share, and the validators of their values.

#include <CLI/CLI.hpp>
#include <string>

#include "commands.hpp"

namespace tvid::cli {

/// A seed: a whole number from 0 to 2^64 − 1, written as such (CLI11 would wrap "-1").
extern const CLI::Validator kSeed;
/// A relative tolerance: a finite number >= 0 (CLI::NonNegativeNumber lets "nan" through).
extern const CLI::Validator kTolerance;
/// An output path given as -o must name something: "" is refused rather than falling back.
extern const CLI::Validator kNonEmptyPath;

/// The experiment, --set, --threads, --quiet and --json.
void add_common(CLI::App& sub, CommonOptions& o);

/// The one file simulate and validate write: -o FILE, or --output-dir DIR (its default
/// name there), and --force.
void add_file_output(CLI::App& sub, EvaluateCommand& cmd, const std::string& what, const std::string& default_name);

/// "pso, lm, nlopt, pso+lm or multistart"
std::string optimizer_names();

}  // namespace tvid::cli

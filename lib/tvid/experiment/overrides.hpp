#pragma once
// Command-line overrides `--set key.path=value`, applied to the experiment's YAML tree
// before it is validated, so an overridden value is checked like one in the file.

#include <yaml-cpp/yaml.h>

#include <string>
#include <vector>

#include "tvid/experiment/experiment.hpp"

namespace tvid {

/// Sets every override in `root` (a mapping). A path segment that is a whole number
/// indexes a list (`windows.estimation.0.time=[1, 2]`); missing sections are created.
/// The value is read as YAML (`[1, 2]`, `{ time: [1, 2] }`, `250`, `rk4`). Throws
/// InputError("--set", 0, key, ...) when a path goes through a value that is not a section.
void apply_overrides(YAML::Node& root, const std::vector<Override>& overrides);

/// Each `--set key=value` text parsed (parse_override, experiment.hpp).
std::vector<Override> parse_overrides(const std::vector<std::string>& texts);

}  // namespace tvid

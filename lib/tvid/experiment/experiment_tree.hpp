#pragma once
// The experiment file's YAML tree as load_experiment reads it: its bytes checked (text,
// one document, a mapping), the command line's overrides applied, and the source that
// names file, line and key in every error. A section that one command alone reads (the
// design: of `tvid design`) is read from this tree after load_experiment has checked the
// rest.

#include <yaml-cpp/yaml.h>

#include <filesystem>
#include <string>
#include <vector>

#include "tvid/experiment/experiment.hpp"
#include "tvid/experiment/yaml_reader.hpp"

namespace tvid {

struct ExperimentTree {
    YAML::Node root;
    YamlSource source;
    std::string sha256;  ///< of the file's bytes as read (before the overrides)
};

/// Throws InputError as load_experiment does for a file that is not an experiment's YAML.
ExperimentTree read_experiment_tree(const std::filesystem::path& file, const std::vector<Override>& overrides);

}  // namespace tvid

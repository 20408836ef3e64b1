#pragma once
// The `model:` section of an experiment: a preset with its constants, or a custom
// lumped torsional network written as `nodes:` and `elements:` (docs/model-library.md).

#include <map>
#include <string>
#include <vector>

#include "tvid/experiment/yaml_reader.hpp"
#include "tvid/model/network_spec.hpp"
#include "tvid/model/presets.hpp"

namespace tvid {

/// A numeric field: a number, or the name of a parameter in `parameter_names`.
Field read_field(const YamlSource& src, const YAML::Node& node, const std::string& path,
                 const std::vector<std::string>& parameter_names);

/// Builds the network. For a custom network `declared_parameters` (the keys of the
/// `parameters:` section, in file order) become its parameters; a field naming
/// anything else is an error. `constants` receives a preset's numeric constants.
NetworkSpec read_model(const YamlMap& model, const std::vector<std::string>& declared_parameters,
                       PresetConstants& constants);

/// Every parameter index some field of the network refers to.
std::vector<bool> parameters_in_use(const NetworkSpec& network);

}  // namespace tvid

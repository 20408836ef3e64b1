#pragma once
// Preset networks with the papers' parametrizations (DESIGN.md "Names the presets use").

#include <map>
#include <string>
#include <vector>

#include "tvid/model/network_spec.hpp"

namespace tvid {

struct PresetInfo {
    std::string name;
    std::string description;
    std::string reference;                     ///< paper and equations
    std::vector<std::string> parameters;       ///< in the order of NetworkSpec::parameter_names
    std::vector<std::string> parameter_units;
    std::vector<std::string> parameter_meanings;
    std::vector<std::string> inputs;
    std::vector<std::string> outputs;
    std::vector<std::string> constants;        ///< keys accepted under `model:`
};

/// All presets, in the order `tvid models` lists them.
const std::vector<PresetInfo>& preset_catalogue();
/// nullptr when there is no preset of that name.
const PresetInfo* find_preset(const std::string& name);

/// Builds the network of a preset. `constants` are the numeric keys given under `model:`
/// (validated by the caller against PresetInfo::constants). Throws std::invalid_argument
/// on an unknown preset.
NetworkSpec build_preset(const std::string& name, const std::map<std::string, double>& constants);

}  // namespace tvid

#pragma once
// Preset networks with the papers' parametrizations (docs/model-library.md, the presets cvt_clearance and engine_block).

#include <map>
#include <stdexcept>
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

/// The constants given under `model:` (a number, or a list such as a firing order).
using PresetConstants = std::map<std::string, std::vector<double>>;

/// A constant a preset cannot use; `constant` names it.
class PresetConstantError : public std::invalid_argument {
public:
    PresetConstantError(std::string constant, const std::string& problem)
        : std::invalid_argument(problem), constant_(std::move(constant)) {}
    const std::string& constant() const { return constant_; }

private:
    std::string constant_;
};

/// Builds the network of a preset from its constants (keys checked by the caller against
/// PresetInfo::constants; values checked here: PresetConstantError). Throws
/// std::invalid_argument on an unknown preset.
NetworkSpec build_preset(const std::string& name, const PresetConstants& constants);

}  // namespace tvid

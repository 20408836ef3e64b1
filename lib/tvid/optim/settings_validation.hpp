#pragma once
// The one check of each optimizer's settings (after Ceres' Solver::Options::IsValid): the
// first problem found, as the settings key at fault and what is wrong with it. The
// experiment reader turns it into "FILE:LINE: estimation.<section>.<key>: <message>".

#include <optional>
#include <string>

#include "tvid/optim/lm_options.hpp"
#include "tvid/optim/multistart_options.hpp"
#include "tvid/optim/nlopt_options.hpp"
#include "tvid/optim/pso_options.hpp"

namespace tvid {

struct SettingsProblem {
    std::string key;       ///< the key in the optimizer's section, e.g. "particles"
    std::string message;   ///< what is wrong, e.g. "particles must be between 1 and 1000000"
    bool missing = false;  ///< the key is missing (reported at the section, not at the key)
};

std::optional<SettingsProblem> validate(const PsoSettings& settings);
std::optional<SettingsProblem> validate(const LmSettings& settings);
/// Also that the algorithm names are NLopt's, and the local algorithm fits the global one.
std::optional<SettingsProblem> validate(const NloptSettings& settings);
std::optional<SettingsProblem> validate(const MultistartSettings& settings);

}  // namespace tvid

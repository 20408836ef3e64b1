#include "tvid/optim/lm_options.hpp"

namespace tvid {

std::optional<SettingsProblem> validate(const LmSettings& s) {
    if (s.max_iterations < 0 || s.max_iterations > 1000000) return settings_problem("max_iterations", "must be between 0 and 1e6");
    for (const auto& [key, value] : {std::pair{"ftol", s.ftol}, std::pair{"xtol", s.xtol}, std::pair{"gtol", s.gtol},
                                     std::pair{"stol", s.stol}})
        if (!(value >= 0)) return settings_problem(key, "a tolerance cannot be negative");
    return std::nullopt;
}

}  // namespace tvid

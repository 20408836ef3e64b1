#include "tvid/optim/multistart_options.hpp"

namespace tvid {

std::optional<SettingsProblem> validate(const MultistartSettings& s) {
    if (s.starts < 1 || s.starts > 100000) return settings_problem("starts", "starts must be between 1 and 1e5");
    if (s.max_iterations && (*s.max_iterations < 1 || *s.max_iterations > 1000000))
        return settings_problem("max_iterations", "must be between 1 and 1e6 (leave it out for lm.max_iterations)");
    if (s.max_draws < 1 || s.max_draws > 1000) return settings_problem("max_draws", "must be between 1 and 1000");
    if (s.race_iterations < 1 || s.race_iterations > 1000000)
        return settings_problem("race_iterations", "must be between 1 and 1e6");
    return std::nullopt;
}

}  // namespace tvid

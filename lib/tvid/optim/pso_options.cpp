#include "tvid/optim/pso_options.hpp"

namespace tvid {

std::optional<SettingsProblem> validate(const PsoSettings& s) {
    if (s.grid < 1 || s.grid > 1000) return settings_problem("grid", "grid points per parameter must be between 1 and 1000");
    if (s.particles < 1 || s.particles > 1000000) return settings_problem("particles", "particles must be between 1 and 1000000");
    if (s.iterations < 0 || s.iterations > 100000000) return settings_problem("iterations", "iterations must be between 0 and 1e8");
    for (const auto& [key, value] : {std::pair{"w", s.w}, std::pair{"c1", s.c1}, std::pair{"c2", s.c2}})
        if (value < 0) return settings_problem(key, "must not be negative (the random factors are drawn from [0, value])");
    return std::nullopt;
}

}  // namespace tvid

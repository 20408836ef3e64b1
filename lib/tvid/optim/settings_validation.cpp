#include "tvid/optim/settings_validation.hpp"

#include "tvid/optim/nlopt_algorithms.hpp"

namespace tvid {

namespace {

std::optional<SettingsProblem> problem(std::string key, std::string message) {
    return SettingsProblem{std::move(key), std::move(message)};
}

}  // namespace

std::optional<SettingsProblem> validate(const PsoSettings& s) {
    if (s.grid < 1 || s.grid > 1000) return problem("grid", "grid points per parameter must be between 1 and 1000");
    if (s.particles < 1 || s.particles > 1000000) return problem("particles", "particles must be between 1 and 1000000");
    if (s.iterations < 0 || s.iterations > 100000000) return problem("iterations", "iterations must be between 0 and 1e8");
    for (const auto& [key, value] : {std::pair{"w", s.w}, std::pair{"c1", s.c1}, std::pair{"c2", s.c2}})
        if (value < 0) return problem(key, "must not be negative (the random factors are drawn from [0, value])");
    return std::nullopt;
}

std::optional<SettingsProblem> validate(const LmSettings& s) {
    if (s.max_iterations < 0 || s.max_iterations > 1000000) return problem("max_iterations", "must be between 0 and 1e6");
    for (const auto& [key, value] : {std::pair{"ftol", s.ftol}, std::pair{"xtol", s.xtol}, std::pair{"gtol", s.gtol},
                                     std::pair{"stol", s.stol}})
        if (!(value >= 0)) return problem(key, "a tolerance cannot be negative");
    return std::nullopt;
}

std::optional<SettingsProblem> validate(const NloptSettings& s) {
    const auto algorithm = find_nlopt_algorithm(s.algorithm);
    if (!algorithm) return problem("algorithm", "NLopt has no algorithm '" + s.algorithm + "'; valid: " + nlopt_algorithm_list());
    if (!s.local_algorithm.empty()) {
        const auto local = find_nlopt_algorithm(s.local_algorithm);
        if (!local || local->global || local->takes_local) {
            std::string locals;
            for (const NloptAlgorithm& a : nlopt_algorithms())
                if (!a.global && !a.takes_local) locals += (locals.empty() ? "" : ", ") + a.name;
            return problem("local_algorithm", "'" + s.local_algorithm + "' is not a local NLopt algorithm; valid: " + locals);
        }
        if (!algorithm->takes_local)
            return problem("local_algorithm",
                           algorithm->name + " runs no local algorithm (only the MLSL and AUGLAG families do)");
    } else if (algorithm->needs_local) {
        return SettingsProblem{"local_algorithm",
                               "(" + algorithm->name + " runs a local algorithm: e.g. local_algorithm: LN_BOBYQA)", true};
    }
    if (s.max_evaluations < 1 || s.max_evaluations > 2000000000) return problem("max_evaluations", "must be between 1 and 2e9");
    if (!(s.max_seconds >= 0)) return problem("max_seconds", "a time limit cannot be negative (0: none)");
    for (const auto& [key, value] : {std::pair{"xtol_rel", s.xtol_rel}, std::pair{"ftol_rel", s.ftol_rel}})
        if (!(value >= 0)) return problem(key, "a tolerance cannot be negative");
    if (s.population < 0 || s.population > 1000000)
        return problem("population", "must be between 0 (NLopt's default) and 1e6");
    return std::nullopt;
}

std::optional<SettingsProblem> validate(const MultistartSettings& s) {
    if (s.starts < 1 || s.starts > 100000) return problem("starts", "starts must be between 1 and 1e5");
    if (s.max_iterations && (*s.max_iterations < 1 || *s.max_iterations > 1000000))
        return problem("max_iterations", "must be between 1 and 1e6 (leave it out for lm.max_iterations)");
    if (s.max_draws < 1 || s.max_draws > 1000) return problem("max_draws", "must be between 1 and 1000");
    return std::nullopt;
}

}  // namespace tvid

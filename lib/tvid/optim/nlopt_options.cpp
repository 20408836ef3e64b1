#include "tvid/optim/nlopt_options.hpp"

#include "tvid/optim/nlopt_algorithms.hpp"

namespace tvid {

std::optional<SettingsProblem> validate(const NloptSettings& s) {
    const auto algorithm = find_nlopt_algorithm(s.algorithm);
    if (!algorithm) return settings_problem("algorithm", "NLopt has no algorithm '" + s.algorithm + "'; valid: " + nlopt_algorithm_list());
    if (!s.local_algorithm.empty()) {
        const auto local = find_nlopt_algorithm(s.local_algorithm);
        if (!local || local->global || local->takes_local) {
            std::string locals;
            for (const NloptAlgorithm& a : nlopt_algorithms())
                if (!a.global && !a.takes_local) locals += (locals.empty() ? "" : ", ") + a.name;
            return settings_problem("local_algorithm", "'" + s.local_algorithm + "' is not a local NLopt algorithm; valid: " + locals);
        }
        if (!algorithm->takes_local)
            return settings_problem("local_algorithm",
                           algorithm->name + " runs no local algorithm (only the MLSL and AUGLAG families do)");
    } else if (algorithm->needs_local) {
        return SettingsProblem{"local_algorithm",
                               "(" + algorithm->name + " runs a local algorithm: e.g. local_algorithm: LN_BOBYQA)", true};
    }
    if (s.max_evaluations < 1 || s.max_evaluations > 2000000000) return settings_problem("max_evaluations", "must be between 1 and 2e9");
    if (!(s.max_seconds >= 0)) return settings_problem("max_seconds", "a time limit cannot be negative (0: none)");
    for (const auto& [key, value] : {std::pair{"xtol_rel", s.xtol_rel}, std::pair{"ftol_rel", s.ftol_rel}})
        if (!(value >= 0)) return settings_problem(key, "a tolerance cannot be negative");
    if (s.population < 0 || s.population > 1000000)
        return settings_problem("population", "must be between 0 (NLopt's default) and 1e6");
    return std::nullopt;
}

}  // namespace tvid

#include "tvid/experiment/optimizer_settings_reader.hpp"

#include "tvid/optim/nlopt_algorithms.hpp"

namespace tvid {

OptimizerKind read_optimizer_kind(const YamlMap& estimation) {
    const std::string name = estimation.choice("optimizer", {"pso", "lm", "nlopt", "pso+lm", "multistart"});
    for (OptimizerKind kind : {OptimizerKind::pso, OptimizerKind::lm, OptimizerKind::nlopt, OptimizerKind::pso_lm,
                               OptimizerKind::multistart})
        if (name == optimizer_name(kind)) return kind;
    return OptimizerKind::pso;
}

NloptSettings read_nlopt(const YamlMap& m) {
    m.allow_only({"algorithm", "local_algorithm", "max_evaluations", "max_seconds", "xtol_rel", "ftol_rel",
                  "population", "seed"});
    NloptSettings s;
    if (m.has("algorithm")) {
        const auto a = find_nlopt_algorithm(m.text("algorithm"));
        if (!a)
            m.fail("algorithm", "NLopt has no algorithm '" + m.text("algorithm") + "'; valid: " + nlopt_algorithm_list());
        s.algorithm = a->name;
    }
    const NloptAlgorithm algorithm = *find_nlopt_algorithm(s.algorithm);
    if (m.has("local_algorithm")) {
        const auto local = find_nlopt_algorithm(m.text("local_algorithm"));
        std::string locals;
        for (const NloptAlgorithm& a : nlopt_algorithms())
            if (!a.global && !a.takes_local) locals += (locals.empty() ? "" : ", ") + a.name;
        if (!local || local->global || local->takes_local)
            m.fail("local_algorithm", "'" + m.text("local_algorithm") + "' is not a local NLopt algorithm; valid: " + locals);
        if (!algorithm.takes_local)
            m.fail("local_algorithm", algorithm.name + " runs no local algorithm (only the MLSL and AUGLAG families do)");
        s.local_algorithm = local->name;
    } else if (algorithm.needs_local) {
        m.fail_missing("local_algorithm", "(" + algorithm.name + " runs a local algorithm: e.g. local_algorithm: LN_BOBYQA)");
    }
    if (m.has("max_evaluations")) {
        s.max_evaluations = m.integer("max_evaluations");
        if (s.max_evaluations < 1 || s.max_evaluations > 2000000000)
            m.fail("max_evaluations", "must be between 1 and 2e9");
    }
    if (m.has("max_seconds")) {
        s.max_seconds = m.number("max_seconds");
        if (!(s.max_seconds >= 0)) m.fail("max_seconds", "a time limit cannot be negative (0: none)");
    }
    for (const char* key : {"xtol_rel", "ftol_rel"}) {
        if (!m.has(key)) continue;
        const double v = m.number(key);
        if (!(v >= 0)) m.fail(key, "a tolerance cannot be negative");
        (std::string(key) == "xtol_rel" ? s.xtol_rel : s.ftol_rel) = v;
    }
    if (m.has("population")) {
        const long long n = m.integer("population");
        if (n < 0 || n > 1000000) m.fail("population", "must be between 0 (NLopt's default) and 1e6");
        s.population = static_cast<int>(n);
    }
    if (m.has("seed")) {
        const long long seed = m.integer("seed");
        if (seed < 0) m.fail("seed", "the seed must not be negative");
        s.seed = static_cast<std::uint64_t>(seed);
    }
    return s;
}

MultistartSettings read_multistart(const YamlMap& m) {
    m.allow_only({"starts", "seed", "max_iterations"});
    MultistartSettings s;
    if (m.has("starts")) {
        const long long n = m.integer("starts");
        if (n < 1 || n > 100000) m.fail("starts", "starts must be between 1 and 1e5");
        s.starts = static_cast<int>(n);
    }
    if (m.has("seed")) {
        const long long seed = m.integer("seed");
        if (seed < 0) m.fail("seed", "the seed must not be negative");
        s.seed = static_cast<std::uint64_t>(seed);
    }
    if (m.has("max_iterations")) {
        const long long n = m.integer("max_iterations");
        if (n < 1 || n > 1000000) m.fail("max_iterations", "must be between 1 and 1e6 (leave it out for lm.max_iterations)");
        s.max_iterations = static_cast<int>(n);
    }
    return s;
}

void check_search_box(const YamlMap& parameters, const std::vector<ParameterSetting>& settings,
                      const EstimationSettings& estimation) {
    const bool nlopt = estimation.optimizer == OptimizerKind::nlopt;
    const bool global = nlopt && find_nlopt_algorithm(estimation.nlopt.algorithm)->global;
    const bool multistart = estimation.optimizer == OptimizerKind::multistart;
    for (const ParameterSetting& p : settings) {
        if (p.fixed) continue;
        if (global && !(p.has_min && p.has_max))
            parameters.fail(p.name, "the global NLopt algorithm " + estimation.nlopt.algorithm +
                                        " searches within the bounds: give both min and max");
        if (multistart && !p.range && !(p.has_min && p.has_max))
            parameters.fail(p.name, "multistart samples its starts in the search box: give range: [a, b] or both min and max");
    }
}

}  // namespace tvid

#pragma once
// The optimizer kind `nlopt`: any NLopt algorithm by name, from init, and its settings
// section `nlopt:`; a global algorithm searches within the bounds.

#include <string>
#include <vector>

#include "tvid/experiment/optimizer_kinds/optimizer_traits.hpp"
#include "tvid/experiment/optimizer_kinds/settings_reading.hpp"
#include "tvid/optim/nlopt_algorithms.hpp"
#include "tvid/optim/nlopt_options.hpp"

namespace tvid {

struct NloptKind {
    static constexpr const char* name = "nlopt";
    static constexpr const char* summary = "any NLopt algorithm by name, from init";
    static constexpr OptimizerTraits traits{};

    // ---- its section: `nlopt: { algorithm: LN_BOBYQA, local_algorithm: LN_SBPLX, max_evaluations: 5000,
    //      max_seconds: 600, xtol_rel: 1e-8, ftol_rel: 1e-12, population: 0, seed: 1 }`
    using Settings = NloptSettings;
    static constexpr const char* keys[] = {"algorithm", "local_algorithm", "max_evaluations", "max_seconds",
                                           "xtol_rel",  "ftol_rel",        "population",      "seed"};

    template <class Map, class Estimation>
    static void read(const Map& m, Estimation& estimation) {
        namespace r = settings_reading;
        NloptSettings& s = estimation.nlopt;
        if (m.has("algorithm")) s.algorithm = m.text("algorithm");
        if (m.has("local_algorithm")) s.local_algorithm = m.text("local_algorithm");
        if (m.has("max_evaluations")) s.max_evaluations = m.integer("max_evaluations");
        if (m.has("max_seconds")) s.max_seconds = m.number("max_seconds");
        if (m.has("xtol_rel")) s.xtol_rel = m.number("xtol_rel");
        if (m.has("ftol_rel")) s.ftol_rel = m.number("ftol_rel");
        if (m.has("population")) s.population = r::integer(m, "population");
        if (m.has("seed")) s.seed = r::seed(m);
        r::fail_on_problem(m, validate(s));
        // NLopt's own spelling of the names given.
        s.algorithm = find_nlopt_algorithm(s.algorithm)->name;
        if (!s.local_algorithm.empty()) s.local_algorithm = find_nlopt_algorithm(s.local_algorithm)->name;
    }

    /// A global NLopt algorithm searches within the bounds.
    template <class Map, class Parameter, class Estimation>
    static void check_parameters(const Map& parameters, const std::vector<Parameter>& settings,
                                 const Estimation& estimation) {
        if (!find_nlopt_algorithm(estimation.nlopt.algorithm)->global) return;
        for (const Parameter& p : settings)
            if (!p.fixed && !(p.has_min && p.has_max))
                parameters.fail(p.name, "the global NLopt algorithm " + estimation.nlopt.algorithm +
                                            " searches within the bounds: give both min and max");
    }
};

}  // namespace tvid

#pragma once
// The optimizer kind `multistart`: Levenberg–Marquardt from Latin-hypercube starts of the
// range box, and its settings section `multistart:` (each start's LM runs on `lm:`).

#include "tvid/experiment/optimizer_kinds/optimizer_traits.hpp"
#include "tvid/experiment/optimizer_kinds/settings_reading.hpp"
#include "tvid/optim/multistart_options.hpp"

namespace tvid {

struct MultistartKind {
    static constexpr const char* name = "multistart";
    static constexpr const char* summary = "Levenberg-Marquardt from Latin-hypercube starts of the box";
    static constexpr OptimizerTraits traits{.least_squares = true, .samples_box = true};

    // ---- its section: `multistart: { starts: 8, seed: 1, max_iterations: 100, max_draws: 10, race: true,
    //      race_iterations: 4 }`
    using Settings = MultistartSettings;
    static constexpr const char* keys[] = {"starts", "seed", "max_iterations", "max_draws", "race", "race_iterations"};

    template <class Map, class Estimation>
    static void read(const Map& m, Estimation& estimation) {
        namespace r = settings_reading;
        MultistartSettings& s = estimation.multistart;
        if (m.has("starts")) s.starts = r::integer(m, "starts");
        if (m.has("seed")) s.seed = r::seed(m);
        if (m.has("max_iterations")) s.max_iterations = r::integer(m, "max_iterations");
        if (m.has("max_draws")) s.max_draws = r::integer(m, "max_draws");
        if (m.has("race")) s.race = m.flag("race");
        if (m.has("race_iterations")) s.race_iterations = r::integer(m, "race_iterations");
        r::fail_on_problem(m, validate(s));
    }
};

}  // namespace tvid

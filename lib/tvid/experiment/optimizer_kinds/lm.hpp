#pragma once
// The optimizer kind `lm`: Levenberg–Marquardt least squares from init (the methodology
// paper), and its settings section `lm:`, which also says how the Jacobian is formed for
// every optimizer's standard errors (`jacobian:`).

#include "tvid/experiment/optimizer_kinds/optimizer_traits.hpp"
#include "tvid/experiment/optimizer_kinds/settings_reading.hpp"
#include "tvid/optim/lm_options.hpp"

namespace tvid {

struct LmKind {
    static constexpr const char* name = "lm";
    static constexpr const char* summary = "Levenberg-Marquardt least squares from init (the methodology paper)";
    static constexpr OptimizerTraits traits{.least_squares = true, .starts_at_init = true};

    // ---- its section: `lm: { max_iterations: 200, ftol, xtol, gtol: 1e-10, stol: 0.1, jacobian: sensitivity }`
    using Settings = LmSettings;
    static constexpr const char* keys[] = {"max_iterations", "ftol", "xtol", "gtol", "stol", "jacobian"};

    template <class Map, class Estimation>
    static void read(const Map& m, Estimation& estimation) {
        LmSettings& s = estimation.lm;
        if (m.has("max_iterations")) s.max_iterations = settings_reading::integer(m, "max_iterations");
        if (m.has("ftol")) s.ftol = m.number("ftol");
        if (m.has("xtol")) s.xtol = m.number("xtol");
        if (m.has("gtol")) s.gtol = m.number("gtol");
        if (m.has("stol")) s.stol = m.number("stol");
        settings_reading::fail_on_problem(m, validate(s));
        if (m.has("jacobian"))
            estimation.jacobian = m.choice("jacobian", {"sensitivity", "fd"}) == "fd" ? decltype(estimation.jacobian)::fd
                                                                                     : decltype(estimation.jacobian)::sensitivity;
    }
};

}  // namespace tvid

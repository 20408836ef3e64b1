#pragma once
// The optimizer kind `pso`: the particle swarm (Yoshida & Takamatsu eqs. 24–27) over the
// search box, and its settings section `pso:`.

#include <string>

#include "tvid/experiment/optimizer_kinds/optimizer_traits.hpp"
#include "tvid/experiment/optimizer_kinds/settings_reading.hpp"
#include "tvid/optim/pso_options.hpp"

namespace tvid {

struct PsoKind {
    static constexpr const char* name = "pso";
    static constexpr const char* summary = "the particle swarm (Yoshida & Takamatsu) over the search box";
    static constexpr OptimizerTraits traits{.swarm = true};

    // ---- its section: `pso: { start: grid, grid: 2, iterations: 250, w: 1, c1: 0.4, c2: 0.4, seed: 1, ... }`
    using Settings = PsoSettings;
    static constexpr const char* keys[] = {"start", "grid", "particles", "iterations", "w",
                                           "c1",    "c2",   "seed",      "draw",       "velocity_first"};

    template <class Map, class Estimation>
    static void read(const Map& m, Estimation& estimation) {
        namespace r = settings_reading;
        PsoSettings& s = estimation.pso;
        if (m.has("start")) {
            const std::string start = m.choice("start", {"grid", "latin_hypercube", "uniform"});
            s.start = start == "grid" ? PsoStart::grid : start == "uniform" ? PsoStart::uniform : PsoStart::latin_hypercube;
        }
        if (m.has("grid")) s.grid = r::integer(m, "grid");
        if (m.has("particles")) s.particles = r::integer(m, "particles");
        if (m.has("iterations")) s.iterations = r::integer(m, "iterations");
        if (m.has("w")) s.w = m.number("w");
        if (m.has("c1")) s.c1 = m.number("c1");
        if (m.has("c2")) s.c2 = m.number("c2");
        if (m.has("seed")) s.seed = r::seed(m);
        if (m.has("draw")) {
            const std::string d = m.choice("draw", {"per_iteration", "per_particle", "per_dimension"});
            s.draw = d == "per_iteration"  ? PsoRandomDraw::per_iteration
                     : d == "per_particle" ? PsoRandomDraw::per_particle
                                           : PsoRandomDraw::per_dimension;
        }
        if (m.has("velocity_first")) s.velocity_first = m.flag("velocity_first");
        r::fail_on_problem(m, validate(s));
    }
};

}  // namespace tvid

#pragma once
// Options of the particle swarm (Yoshida & Takamatsu eq. 24–27), with the paper's defaults.

#include "tvid/optim/settings_problem.hpp"
#include <cstdint>

namespace tvid {

enum class PsoStart { grid, latin_hypercube, uniform };
enum class PsoRandomDraw { per_iteration, per_particle, per_dimension };

struct PsoSettings {
    PsoStart start = PsoStart::grid;
    int grid = 2;                ///< n: particles on the n^M grid of the range box (eq. 26)
    int particles = 64;          ///< for latin_hypercube / uniform starts
    int iterations = 250;        ///< swarm updates after the initial evaluation (k = 1 … kmax)
    double w = 1.0, c1 = 0.4, c2 = 0.4;  ///< η0 ~ U[0,w], η1 ~ U[0,c1], η2 ~ U[0,c2]
    /// How often the η are drawn. The paper writes η(k) but does not say; on the shipped
    /// CVT data per-dimension draws reach a 2-10x lower cost than the others
    /// (bench/pso_variants.cpp, docs/experiment-format.md), so they are the default.
    PsoRandomDraw draw = PsoRandomDraw::per_dimension;
    bool velocity_first = false; ///< false: p(k+1) = p(k) + v(k) as eq. 24 prints; true: + v(k+1)
    std::uint64_t seed = 1;
};

/// The first problem of the settings, or none.
std::optional<SettingsProblem> validate(const PsoSettings& settings);

}  // namespace tvid

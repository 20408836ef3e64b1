#pragma once
// The optimizer kind `pso+lm`: the swarm, then Levenberg–Marquardt from its best particle.
// It runs on the sections of both (`pso:` and `lm:`) and has none of its own.

#include "tvid/experiment/optimizer_kinds/optimizer_traits.hpp"

namespace tvid {

struct PsoLmKind {
    static constexpr const char* name = "pso+lm";
    static constexpr const char* summary = "the swarm, then Levenberg-Marquardt from its best particle";
    static constexpr OptimizerTraits traits{.least_squares = true, .swarm = true};
};

}  // namespace tvid

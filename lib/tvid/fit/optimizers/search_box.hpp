#pragma once
// The swarm's and multistart's SearchBox of an identification problem: its bounds, and the
// range box where the particles or starts are placed.

#include "tvid/estimation/identification_problem.hpp"
#include "tvid/optim/pso.hpp"

namespace tvid {

inline SearchBox search_box(const IdentificationProblem& problem) {
    return SearchBox{problem.lower(), problem.upper(), problem.range_lower(), problem.range_upper()};
}

}  // namespace tvid

#pragma once
// Where the optimizers search an identification problem: in the coordinates of its free
// parameters' scales (u = ln p for `scale: log`, u = p otherwise; optim/parameter_scaling.hpp),
// within its bounds, from its init, the swarm's particles and multistart's starts placed in
// its range box, all mapped to those coordinates. Every optimizer's row takes them from here,
// evaluates the model through the scaling's adapters and maps its summary back to the
// parameters.

#include <vector>

#include "tvid/estimation/identification_problem.hpp"
#include "tvid/optim/parameter_scaling.hpp"
#include "tvid/optim/pso.hpp"

namespace tvid {

inline ParameterScaling search_scaling(const IdentificationProblem& problem) {
    return ParameterScaling(problem.scales(), problem.lower(), problem.upper());
}

/// The bounds and the range box in search coordinates.
inline SearchBox search_box(const IdentificationProblem& problem) {
    return search_scaling(problem).to_search(
        SearchBox{problem.lower(), problem.upper(), problem.range_lower(), problem.range_upper()});
}

/// The init in search coordinates.
inline std::vector<double> search_initial(const IdentificationProblem& problem) {
    return search_scaling(problem).to_search(problem.initial());
}

}  // namespace tvid

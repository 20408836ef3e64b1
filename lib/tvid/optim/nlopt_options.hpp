#pragma once
// Options of an NLopt minimization (nlopt_minimizer.hpp): any NLopt algorithm by name,
// local or global, with its budgets and tolerances.

#include "tvid/optim/settings_problem.hpp"
#include <cstdint>
#include <string>

namespace tvid {

struct NloptSettings {
    /// NLopt's name of the algorithm without the NLOPT_ prefix, e.g. LN_BOBYQA, LD_LBFGS,
    /// GN_DIRECT_L, G_MLSL_LDS (nlopt_algorithms.hpp lists them).
    std::string algorithm = "LN_BOBYQA";
    /// The local algorithm of MLSL and AUGLAG (needed by G_MLSL, G_MLSL_LDS, AUGLAG,
    /// AUGLAG_EQ; optional for the others of those families); empty: none.
    std::string local_algorithm;
    long long max_evaluations = 2000;  ///< objective evaluations (a gradient counts as one)
    double max_seconds = 0.0;          ///< wall-time limit; 0: none
    double xtol_rel = 1e-8;            ///< stop when a step changes every parameter by less than this, relatively
    double ftol_rel = 1e-12;           ///< stop when a step changes the cost by less than this, relatively
    int population = 0;                ///< population of CRS2, ISRES, ESCH, MLSL points per round; 0: NLopt's default
    std::uint64_t seed = 1;            ///< seed of the randomized algorithms (nlopt::srand)
};

/// The first problem of the settings, or none.
/// Also that the algorithm names are NLopt's, and the local algorithm fits the global one.
std::optional<SettingsProblem> validate(const NloptSettings& settings);

}  // namespace tvid

#pragma once
// The NLopt algorithms this build of NLopt offers, by the names NLopt gives them
// (nlopt_algorithm_to_string: LN_BOBYQA, GN_DIRECT_L, ...). NLopt's naming convention
// tells what each needs: G = global (searches the whole bounds box, so the bounds must be
// finite), L = local; D = uses the gradient, N = does not; MLSL and AUGLAG run a local
// algorithm inside (G_MLSL, G_MLSL_LDS, AUGLAG, AUGLAG_EQ cannot do without one).

#include <optional>
#include <string>
#include <vector>

namespace tvid {

struct NloptAlgorithm {
    std::string name;          ///< NLopt's name, e.g. "LN_BOBYQA"
    int code = 0;              ///< the nlopt_algorithm value
    bool global = false;       ///< G*: searches the bounds box
    bool gradient = false;     ///< ?D_*: asks for the gradient itself
    bool needs_local = false;  ///< cannot run without a local algorithm
    bool takes_local = false;  ///< runs a local algorithm inside (MLSL, AUGLAG)
    std::string description;   ///< NLopt's description
};

/// The algorithm called `name` (case-insensitive, an NLOPT_ prefix allowed), or nothing
/// when NLopt has no such algorithm or this build of it was compiled without it.
std::optional<NloptAlgorithm> find_nlopt_algorithm(const std::string& name);

/// Every algorithm this build of NLopt offers, in NLopt's order.
std::vector<NloptAlgorithm> nlopt_algorithms();

/// Their names joined by ", " for error messages.
std::string nlopt_algorithm_list();

}  // namespace tvid

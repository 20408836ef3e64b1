#pragma once
// What the reader and the verdict need to know of an optimizer (each kind declares its own,
// experiment/optimizer_kinds/NAME.hpp).

namespace tvid {

struct OptimizerTraits {
    bool least_squares = false;   ///< minimizes Σe² through the residuals (needs cost: l2)
    bool swarm = false;           ///< runs the particle swarm (its search box, its grid start)
    bool samples_box = false;     ///< draws its starts in the range box (needs range or both bounds)
    bool starts_at_init = false;  ///< starts at init: the box is only a bound, never sampled
};

}  // namespace tvid

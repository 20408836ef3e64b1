#pragma once
// How close a fixed-step RK4 simulation is to its stability limit. The network is
// linearised at each estimation window's start (ẋ ≈ A x, A = ∂f/∂x exactly by dual
// numbers), and each eigenvalue λ of A is set against the edge of RK4's stability region
// |1 + z + z²/2 + z³/6 + z⁴/24| ≤ 1 along its own direction: margin = |λh| / r(arg λ),
// with r = 2.785 on the negative real axis and 2.828 on the imaginary one. A margin near
// 1 means a stiff mode (a large damping on a small inertia, a stiff coupling) that a
// slightly larger parameter would turn into a blow-up; above 1 the window is simulated
// only because that mode is not excited.

#include <string>
#include <vector>

#include "tvid/estimation/identification_problem.hpp"
#include "tvid/sim/rk4_stability.hpp"  // rk4_stability_radius

namespace tvid {

struct StepStability {
    bool assessed = false;     ///< false for the adaptive integrators, or when no start could be solved
    std::string window;        ///< the window of the largest margin
    double step = 0.0;         ///< h [s]: the experiment's step over the window's substeps
    std::size_t substeps = 1;  ///< of that window at these parameters (estimation/stable_step.hpp)
    bool implicit = false;     ///< a window too stiff for the substeps, simulated by sdirk3 (`window` names it)
    double margin = 0.0;       ///< the largest |λh| / r(arg λ)
    double rate = 0.0;         ///< |λ| of that eigenvalue [1/s]
    double frequency_hz = 0.0; ///< |Im λ| / 2π
    double damping_ratio = 0.0;///< −Re λ / |λ|
};


/// The margin of the rk4 simulation of `params` (full parameter vector) over the
/// estimation windows' starts; with `starts` (Evaluation::estimation_starts at the same
/// parameters), from those instead of solving them again.
StepStability assess_step_stability(const IdentificationProblem& problem, const std::vector<double>& params,
                                    const std::vector<SolvedStart>* starts = nullptr);

}  // namespace tvid

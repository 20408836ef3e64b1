#pragma once
// The step of a stiff candidate. A fixed-step RK4 simulation blows up once a mode of the
// network passes RK4's stability region at the experiment's step (a large damping on a
// small inertia: |λ| = c/J). Before a window is simulated, its network is linearised at the
// window's start state (exactly, by dual numbers) and the step divided into as many equal
// substeps as bring every mode within kStableMargin of the region's edge in its own
// direction (sim/rk4_stability.hpp). Every fixed-step path of that window (the plain march,
// the warm-up shooting, both sensitivity paths) takes the same substeps, so a candidate's
// cost and Jacobian stay functions of its parameters alone. A candidate that needs none is
// simulated as before; one that does costs what its stable simulation gives instead of a
// failure. The cost is continuous in the parameters except where the number of substeps
// changes, where it steps by the size of the integration error.
//
// A candidate that would need more than kMaxStableSubsteps (a mode hundreds of times
// faster than the step) is simulated by sdirk3 instead, at the experiment's step: an
// L-stable implicit method with the model's exact Jacobian (sim/sdirk3.hpp), in which
// such a mode decays within the step. It is the method `simulation.method: sdirk3` takes,
// so the candidate costs what it would cost there, on every path of the window.

#include <cstddef>

#include "tvid/estimation/problem_definition.hpp"
#include "tvid/estimation/problem_workspace.hpp"

namespace tvid {

/// The largest |λh| over the edge that a simulation is left with (0.9: a tenth of margin).
inline constexpr double kStableMargin = 0.9;
/// At most this many substeps per step: beyond, the window takes sdirk3's implicit steps
/// at the experiment's step rather than an ever finer RK4 step.
inline constexpr std::size_t kMaxStableSubsteps = 64;

/// How window w's simulations step at the parameters set in ws.model, from the
/// linearisation at the state ws.x with inputs ws.u0.
struct StepPlan {
    std::size_t substeps = 1;  ///< RK4 substeps per experiment step (1: an adaptive integrator, or nothing passes the margin)
    bool implicit = false;     ///< beyond kMaxStableSubsteps: sdirk3's steps at the experiment's step instead
};
StepPlan stable_step_plan(const ProblemDefinition& d, const Window& w, ProblemWorkspace& ws);

/// The max_step that window w's fixed-step simulations take on ws (ws.substeps applied;
/// 0, one step per sample, when the experiment asks for that and no substeps are needed).
double window_max_step(const ProblemDefinition& d, const Window& w, const ProblemWorkspace& ws);

/// The simulation settings of window w on ws: the experiment's, with window_max_step, or
/// sdirk3 at the experiment's step when ws.implicit_steps.
SimulationSettings window_settings(const ProblemDefinition& d, const Window& w, const ProblemWorkspace& ws);

}  // namespace tvid

#pragma once
// How a simulation ended, and when a state counts as diverged.

namespace tvid {

enum class SimulationStatus {
    ok,
    not_finite,
    diverged,
    step_budget_exceeded,
    stopped_by_observer,
    stopped_by_request,  ///< a stop request (Ctrl-C, SIGTERM) during an optimizer's run
};

const char* to_string(SimulationStatus s);

/// |θ| or |ω| beyond this is taken as a diverging simulation.
inline constexpr double kDivergenceLimit = 1e12;

}  // namespace tvid

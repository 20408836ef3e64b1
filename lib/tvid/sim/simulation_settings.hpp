#pragma once
// How a simulation integrates the equations of motion: the experiment's `simulation:`
// block, read by the experiment layer and used by everything that simulates.

#include <cstddef>

#include "tvid/sim/integration_methods.hpp"

namespace tvid {

struct SimulationSettings {
    IntegrationMethod method = IntegrationMethod::rk4;
    double max_step = 0.0;       ///< rk4: largest step [s]; 0 (`step: sample`) = one step per sample interval
    double rtol = 1e-6;          ///< dopri5, rosenbrock4
    double atol = 1e-8;          ///< dopri5, rosenbrock4
    std::size_t max_steps = 10'000'000;  ///< step budget per simulation (dopri5, rosenbrock4)
};

/// The most fixed (rk4) steps one simulation of a whole recording may take: more would
/// run for many minutes per simulation, and the step counts would no longer be exact.
/// The experiment loader refuses a `simulation.step` (or a time column) that asks for
/// more; a fixed-step crossing (FixedSubsteps) stops with step_budget_exceeded rather than step past it.
inline constexpr double kMaxFixedStepsPerSimulation = 1e9;

}  // namespace tvid

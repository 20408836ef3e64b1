#pragma once
// The loops that march a simulation over the recording's sample grid and hand the state
// to an observer at every sample, one per kind of stepper, after Boost.Odeint's
// integrate_times (boost/numeric/odeint/integrate/detail/integrate_times.hpp): step up to
// the next requested time, then observe. Every simulation of the library goes through
// one of them; what differs between simulations (the stepper, the state's scalar type,
// what is watched) is in the callbacks.
//  - march_fixed_steps: fixed steps, each sample interval split into equal substeps
//    of at most max_step (one per interval without it), as Yoshida & Takamatsu's RK4 at the
//    sampling interval;
//  - march_controlled_steps: a controlled (error-estimating) stepper, restarted at
//    every sample so that the kinks of the linearly interpolated inputs fall on step
//    boundaries, within a budget of steps.
// An observer returns SimulationStatus::ok to go on; any other status ends the march
// with it.

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <vector>

#include "tvid/sim/simulation_status.hpp"

namespace tvid {

/// The equal substeps a fixed-step integrator takes over a sample interval of length h:
/// one, or as few as keep each at most max_step (> 0; the 1e-9 keeps an interval that is
/// a whole multiple of max_step from taking one more).
inline int substeps_over(double h, double max_step) {
    if (max_step > 0.0 && h > max_step) return static_cast<int>(std::ceil(h / max_step - 1e-9));
    return 1;
}

/// One fixed step of march_fixed_steps: substep `substep` of `substeps` of the interval
/// from sample `sample` to the next, from time t over dt.
struct FixedStep {
    std::size_t sample;
    int substep, substeps;
    double t, dt;
};

/// From sample `start` to `last` of `time`: step(FixedStep) for every substep of each
/// interval, then observe(i + 1) at its end.
template <class Step, class Observe>
SimulationStatus march_fixed_steps(const std::vector<double>& time, std::size_t start, std::size_t last,
                                   double max_step, Step&& step, Observe&& observe) {
    for (std::size_t i = start; i < last; ++i) {
        const double t0 = time[i], h = time[i + 1] - t0;
        const int substeps = substeps_over(h, max_step);
        const double dt = h / substeps;
        for (int s = 0; s < substeps; ++s) step(FixedStep{i, s, substeps, t0 + s * dt, dt});
        const SimulationStatus status = observe(i + 1);
        if (status != SimulationStatus::ok) return status;
    }
    return SimulationStatus::ok;
}

/// What a controlled stepper's attempt at a step did.
struct StepAttempt {
    bool accepted = false;                       ///< taken (t and the state advanced), else to retry with the smaller dt
    SimulationStatus status = SimulationStatus::ok;  ///< not ok: the simulation cannot go on
};

/// From sample `start` to `last` of `time`, at most `max_steps` attempts:
/// enter_interval(i) as the interval from sample i begins, then try_step(t, dt) (which
/// advances t and sets the next dt, as odeint's try_step does) until t reaches the
/// interval's end, then observe(i + 1). The first dt is the first sample interval; each
/// later one is the controller's, cut to end at the next sample.
template <class EnterInterval, class TryStep, class Observe>
SimulationStatus march_controlled_steps(const std::vector<double>& time, std::size_t start, std::size_t last,
                                        std::size_t max_steps, EnterInterval&& enter_interval, TryStep&& try_step,
                                        Observe&& observe) {
    std::size_t steps = 0;
    double dt = (time[std::min(start + 1, last)] - time[start]);
    for (std::size_t i = start; i < last; ++i) {
        enter_interval(i);
        double t = time[i];
        const double t_end = time[i + 1];
        while (t < t_end) {
            if (++steps > max_steps) return SimulationStatus::step_budget_exceeded;
            dt = std::min(dt, t_end - t);
            const StepAttempt attempt = try_step(t, dt);
            if (attempt.status != SimulationStatus::ok) return attempt.status;
            if (!attempt.accepted) {
                if (!(dt > 1e-14 * (1.0 + std::abs(t)))) return SimulationStatus::step_budget_exceeded;
                continue;
            }
            if (t_end - t < 1e-12 * (1.0 + std::abs(t_end))) t = t_end;  // rounding short of the sample
        }
        const SimulationStatus status = observe(i + 1);
        if (status != SimulationStatus::ok) return status;
    }
    return SimulationStatus::ok;
}

}  // namespace tvid

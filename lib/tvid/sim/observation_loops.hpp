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
// with it. A stop request during an optimizer's run (InterruptibleSimulations) ends it too.

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <vector>

#include "tvid/sim/simulation_settings.hpp"
#include "tvid/sim/simulation_status.hpp"
#include "tvid/util/stop_request.hpp"

namespace tvid {

/// The equal substeps a fixed-step integrator takes over a sample interval of length h:
/// one, or as few as keep each at most max_step (> 0; the 1e-9 keeps an interval that is
/// a whole multiple of max_step from taking one more). A double: for a tiny step or a
/// long gap in the time column the count can pass any integer type.
inline double substeps_over(double h, double max_step) {
    if (max_step > 0.0 && h > max_step) return std::ceil(h / max_step - 1e-9);
    return 1.0;
}

/// What fixed steps of at most max_step cost over a whole time column.
struct FixedStepCount {
    double total = 0.0;            ///< steps over the whole recording
    double longest = 0.0;          ///< steps over the longest sample interval
    std::size_t longest_at = 0;    ///< that interval's first sample
};

inline FixedStepCount fixed_steps_over(const std::vector<double>& time, double max_step) {
    FixedStepCount c;
    for (std::size_t i = 0; i + 1 < time.size(); ++i) {
        const double n = substeps_over(time[i + 1] - time[i], max_step);
        c.total += n;
        if (n > c.longest) c.longest = n, c.longest_at = i;
    }
    return c;
}

/// How many samples or steps a march takes between looks at the stop request (a relaxed
/// atomic load: free at this spacing, and a stop reaches a 1e9-step simulation in
/// milliseconds).
inline constexpr std::size_t kStopCheckInterval = 4096;

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
        const double substep_count = substeps_over(h, max_step);
        // The loader refuses such steps; a caller that did not load an experiment stops here.
        if (!(substep_count <= kMaxFixedStepsPerSimulation)) return SimulationStatus::step_budget_exceeded;
        const int substeps = static_cast<int>(substep_count);
        const double dt = h / substeps;
        if ((i - start) % kStopCheckInterval == 0 && simulation_stop_requested())
            return SimulationStatus::stopped_by_request;
        for (int s = 0; s < substeps; ++s) {
            step(FixedStep{i, s, substeps, t0 + s * dt, dt});
            if (static_cast<std::size_t>(s) % kStopCheckInterval == kStopCheckInterval - 1 && simulation_stop_requested())
                return SimulationStatus::stopped_by_request;
        }
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
            if (steps % kStopCheckInterval == 0 && simulation_stop_requested())
                return SimulationStatus::stopped_by_request;
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

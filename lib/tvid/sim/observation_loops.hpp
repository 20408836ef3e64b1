#pragma once
// The one loop that marches a simulation over the recording's sample grid, after
// Boost.Odeint's integrate_times (boost/numeric/odeint/integrate/detail/integrate_times.hpp):
// cross the interval up to the next sample, then look. Every simulation of the library
// (plain, stiff, with sensitivities, packed, batched) goes through `march_over_samples`;
// what differs between them is in two objects it is handed:
//  - how an interval is crossed, one kind per stepper category: `FixedSubsteps` (fixed
//    steps, each sample interval split into equal substeps of at most max_step, one per
//    interval without it, as Yoshida & Takamatsu's RK4 at the sampling interval) or
//    `ControlledSteps` (an error-estimating stepper, restarted at every sample so that the
//    kinks of the linearly interpolated inputs fall on step boundaries, within a budget of
//    steps);
//  - the hooks at the samples (begin where the march starts, arrive at each later sample):
//    `SampleHooks` reads the inputs there, restarts and samples the elements with memory
//    (digital controllers) and hands over to the observer.
// A crossing or an observer returns SimulationStatus::ok to go on; any other status ends
// the march with it. A stop request during an optimizer's run (InterruptibleSimulations)
// ends it too.

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <utility>
#include <vector>

#include "tvid/channels/input_channels.hpp"
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

/// The one sample loop: hooks.begin(start), then for every interval from sample i < last,
/// cross(i) brings the state from time[i] to time[i + 1] and hooks.arrive(i + 1) looks at it.
template <class CrossInterval, class Hooks>
SimulationStatus march_over_samples(std::size_t start, std::size_t last, CrossInterval&& cross, Hooks&& hooks) {
    hooks.begin(start);
    for (std::size_t i = start; i < last; ++i) {
        if ((i - start) % kStopCheckInterval == 0 && simulation_stop_requested())
            return SimulationStatus::stopped_by_request;
        SimulationStatus status = cross(i);
        if (status != SimulationStatus::ok) return status;
        status = hooks.arrive(i + 1);
        if (status != SimulationStatus::ok) return status;
    }
    return SimulationStatus::ok;
}

/// One fixed step of FixedSubsteps: substep `substep` of `substeps` of the interval
/// from sample `sample` to the next, from time t over dt.
struct FixedStep {
    std::size_t sample;
    int substep, substeps;
    double t, dt;
};

/// Crosses a sample interval in equal fixed steps: step(FixedStep) for each, then
/// check() (the status of the state reached).
template <class Step, class Check>
class FixedSubsteps {
public:
    FixedSubsteps(const std::vector<double>& time, double max_step, Step step, Check check)
        : time_(&time), max_step_(max_step), step_(std::move(step)), check_(std::move(check)) {}

    SimulationStatus operator()(std::size_t i) {
        const double t0 = (*time_)[i], h = (*time_)[i + 1] - t0;
        const double substep_count = substeps_over(h, max_step_);
        // The loader refuses such steps; a caller that did not load an experiment stops here.
        if (!(substep_count <= kMaxFixedStepsPerSimulation)) return SimulationStatus::step_budget_exceeded;
        const int substeps = static_cast<int>(substep_count);
        const double dt = h / substeps;
        for (int s = 0; s < substeps; ++s) {
            step_(FixedStep{i, s, substeps, t0 + s * dt, dt});
            if (static_cast<std::size_t>(s) % kStopCheckInterval == kStopCheckInterval - 1 && simulation_stop_requested())
                return SimulationStatus::stopped_by_request;
        }
        return check_();
    }

private:
    const std::vector<double>* time_;
    double max_step_;
    Step step_;
    Check check_;
};

/// What a controlled stepper's attempt at a step did.
struct StepAttempt {
    bool accepted = false;                       ///< taken (t and the state advanced), else to retry with the smaller dt
    SimulationStatus status = SimulationStatus::ok;  ///< not ok: the simulation cannot go on
};

/// Crosses a sample interval with a controlled stepper, at most `max_steps` attempts over
/// the march: enter_interval(i) as the interval from sample i begins, then try_step(t, dt)
/// (which advances t and sets the next dt, as odeint's try_step does) until t reaches the
/// interval's end. The first dt is the march's first sample interval; each later one is
/// the controller's, cut to end at the next sample.
template <class EnterInterval, class TryStep>
class ControlledSteps {
public:
    ControlledSteps(const std::vector<double>& time, std::size_t start, std::size_t last, std::size_t max_steps,
                    EnterInterval enter_interval, TryStep try_step)
        : time_(&time), max_steps_(max_steps), dt_(time[std::min(start + 1, last)] - time[start]),
          enter_interval_(std::move(enter_interval)), try_step_(std::move(try_step)) {}

    SimulationStatus operator()(std::size_t i) {
        enter_interval_(i);
        double t = (*time_)[i];
        const double t_end = (*time_)[i + 1];
        while (t < t_end) {
            if (++steps_ > max_steps_) return SimulationStatus::step_budget_exceeded;
            if (steps_ % kStopCheckInterval == 0 && simulation_stop_requested())
                return SimulationStatus::stopped_by_request;
            dt_ = std::min(dt_, t_end - t);
            const StepAttempt attempt = try_step_(t, dt_);
            if (attempt.status != SimulationStatus::ok) return attempt.status;
            if (!attempt.accepted) {
                if (!(dt_ > 1e-14 * (1.0 + std::abs(t)))) return SimulationStatus::step_budget_exceeded;
                continue;
            }
            if (t_end - t < 1e-12 * (1.0 + std::abs(t_end))) t = t_end;  // rounding short of the sample
        }
        return SimulationStatus::ok;
    }

private:
    const std::vector<double>* time_;
    std::size_t max_steps_;
    std::size_t steps_ = 0;
    double dt_;
    EnterInterval enter_interval_;
    TryStep try_step_;
};

/// The hooks at the samples that every simulation shares. Where the march begins: the
/// inputs there, and the elements with memory restarted (`memory.restart(u)`). At each
/// later sample i: the inputs there, the elements with memory sampling the state
/// (`memory.sample(t, u)`: a held output changes only here, between steps), then
/// observe(i). `memory` binds the state the march steps to the model's or the system's
/// restart_sampling and sample (ModelMemory, SystemMemory).
template <class Memory, class Observe>
struct SampleHooks {
    const InputChannels& inputs;
    std::vector<double>& u;
    Memory memory;
    Observe observe;

    void begin(std::size_t start) {
        u.resize(inputs.count());
        inputs.read_sample(start, u.data());
        memory.restart(u);
    }
    SimulationStatus arrive(std::size_t i) {
        inputs.read_sample(i, u.data());
        memory.sample(inputs.time()[i], u);
        return observe(i);
    }
};

template <class Memory, class Observe>
SampleHooks<Memory, Observe> sample_hooks(const InputChannels& inputs, std::vector<double>& u, Memory memory,
                                          Observe observe) {
    return {inputs, u, std::move(memory), std::move(observe)};
}

/// A NetworkModel<T>'s elements with memory at the state x points to.
template <class Model, class T>
struct ModelMemory {
    Model& model;
    const T* x;
    void restart(const std::vector<double>& u) { model.restart_sampling(x, u.data()); }
    void sample(double t, const std::vector<double>& u) { model.sample(t, x, u.data()); }
};

/// An odeint system's elements with memory (its restart_sampling and sample) at state x.
template <class System, class State>
struct SystemMemory {
    System& system;
    const State& x;
    void restart(const std::vector<double>& u) { system.restart_sampling(x, u); }
    void sample(double t, const std::vector<double>& u) { system.sample(t, x, u); }
};

}  // namespace tvid

#pragma once
// Simulation of a network over a span of samples with Boost.Odeint: fixed-step RK4
// (the sampling interval, as Yoshida & Takamatsu does, optionally split into substeps), adaptive
// Dormand–Prince 5(4) with rtol/atol, or the adaptive Rosenbrock 4(3) method for stiff
// models (linearly implicit, with the dual-number Jacobian). The observer sees the state
// at every sample.
// A simulation that produces NaN/inf, grows without bound, or exceeds its step budget
// stops with a status instead of throwing.

#include <algorithm>
#include <boost/numeric/odeint.hpp>
#include <cmath>
#include <cstddef>
#include <functional>
#include <type_traits>
#include <vector>
#include <utility>

#include "tvid/model/network_model.hpp"
#include "tvid/sim/fixed_state_rk4.hpp"
#include "tvid/channels/input_channels.hpp"
#include "tvid/sim/observation_loops.hpp"
#include "tvid/sim/sdirk3.hpp"
#include "tvid/sim/simulation_settings.hpp"
#include "tvid/sim/simulation_status.hpp"
#include "tvid/sim/state_size_dispatch.hpp"
#include "tvid/sim/stiff_network_system.hpp"

namespace tvid {

/// The odeint system: dx/dt = f(x, u(t)) with inputs interpolated at t.
class NetworkSystem {
public:
    NetworkSystem(NetworkModel<double>& model, const InputChannels& inputs, std::vector<double>& u)
        : model_(&model), inputs_(&inputs), u_(&u) {}
    void operator()(const std::vector<double>& x, std::vector<double>& dxdt, double t) {
        ++evaluations;
        inputs_->at(t, hint_, u_->data());
        model_->derivative(x.data(), u_->data(), dxdt.data());
    }
    /// The model's sampled elements restarted at the start and sampled at each later sample.
    void restart_sampling(const std::vector<double>& x, const std::vector<double>& u) {
        model_->restart_sampling(x.data(), u.data());
    }
    void sample(double t, const std::vector<double>& x, const std::vector<double>& u) {
        model_->sample(t, x.data(), u.data());
    }
    std::size_t evaluations = 0;

private:
    NetworkModel<double>* model_;
    const InputChannels* inputs_;
    std::vector<double>* u_;
    std::size_t hint_ = 0;
};

/// Steppers and buffers reused from one simulation to the next (one per thread).
/// The steppers resize their stage buffers whenever the state's size changes (odeint's
/// default resizes only once): the same buffers serve the plain state and augmented
/// sensitivity states of different widths. The check is one size comparison per step.
struct SimulationBuffers {
    using State = std::vector<double>;
    using Rk4 = boost::numeric::odeint::runge_kutta4<State, double, State, double,
                                                     boost::numeric::odeint::range_algebra,
                                                     boost::numeric::odeint::default_operations,
                                                     boost::numeric::odeint::always_resizer>;
    using Dopri5 = boost::numeric::odeint::runge_kutta_dopri5<State, double, State, double,
                                                              boost::numeric::odeint::range_algebra,
                                                              boost::numeric::odeint::default_operations,
                                                              boost::numeric::odeint::always_resizer>;
    std::vector<double> u;
    std::vector<double> u_stages;  ///< inputs at the RK4 stage times (fixed-state RK4)
    Rk4 rk4;
    Dopri5 dopri5;
    StiffBuffers stiff;  ///< rosenbrock4
    Sdirk3 sdirk3;
    // Running totals over every simulate_samples call, for benchmarks.
    std::size_t rhs_evaluations = 0;       ///< f(x, u) with double
    std::size_t jacobian_evaluations = 0;  ///< ∂f/∂x (rosenbrock4, sdirk3)
};

/// Checks the first `checked` entries of x (the model state; sensitivities that may follow
/// it are only checked for being finite).
inline bool state_is_sane(const std::vector<double>& x, SimulationStatus& status,
                          std::size_t checked = static_cast<std::size_t>(-1)) {
    for (std::size_t i = 0; i < x.size(); ++i) {
        const double v = x[i];
        if (!std::isfinite(v)) { status = SimulationStatus::not_finite; return false; }
        if (i < checked && std::abs(v) > kDivergenceLimit) { status = SimulationStatus::diverged; return false; }
    }
    return true;
}

/// Marches any odeint system `system(x, dxdt, t)` over the sample grid of `inputs` from
/// sample `start` to `last` with the integrator of `settings`, calling
/// `observer(i, x, u)` at every sample i in (start, last] with u the inputs at time[i].
/// The observer returns false to stop early. Only x[0 … checked) is tested for divergence.
/// The system's sampled elements (restart_sampling, sample: NetworkSystem,
/// SensitivitySystem) restart at `start` and sample at every later sample, before the
/// observer: every integrator stops at each sample, so a held output changes only
/// between steps.
template <class System, class Observer>
SimulationStatus march_samples(System& system, const InputChannels& inputs, std::size_t start, std::size_t last,
                               std::vector<double>& x, std::size_t checked, const SimulationSettings& settings,
                               SimulationBuffers& buffers, Observer&& observer) {
    namespace odeint = boost::numeric::odeint;
    const SystemMemory<System, std::vector<double>> memory{system, x};
    const auto look = [&](std::size_t i) {
        return observer(i, x, buffers.u) ? SimulationStatus::ok : SimulationStatus::stopped_by_observer;
    };
    if (steps_by_rk4(settings.method)) {
        const auto step = [&](const FixedStep& s) { buffers.rk4.do_step(std::ref(system), x, s.t, s.dt); };
        const auto check = [&] {
            SimulationStatus status = SimulationStatus::ok;
            state_is_sane(x, status, checked);
            return status;
        };
        return march_over_samples(start, last, FixedSubsteps(inputs.time(), settings.max_step, step, check),
                                  sample_hooks(inputs, buffers.u, memory, look));
    }
    // Adaptive Dormand–Prince, the state checked after every step. (A system without a
    // Jacobian, such as the augmented sensitivity system, also marches this way under
    // rosenbrock4; the sensitivities under sdirk3 march in march_sdirk3.)
    auto stepper = odeint::make_controlled(settings.atol, settings.rtol, buffers.dopri5);
    const auto try_step = [&](double& t, double& dt) {
        StepAttempt attempt;
        attempt.accepted = stepper.try_step(std::ref(system), x, t, dt) != odeint::fail;
        if (attempt.accepted) state_is_sane(x, attempt.status, checked);
        return attempt;
    };
    // dopri5 reuses its last stage as the next step's first (FSAL): after a held output
    // changed at the sample, that stage is stale.
    const auto look_afresh = [&](std::size_t i) {
        const SimulationStatus status = look(i);
        stepper.reset();
        return status;
    };
    const auto no_interval_setup = [](std::size_t) {};
    return march_over_samples(
        start, last, ControlledSteps(inputs.time(), start, last, settings.max_steps, no_interval_setup, try_step),
        sample_hooks(inputs, buffers.u, memory, look_afresh));
}

/// march_samples for rosenbrock4: adaptive Rosenbrock 4(3) steps (odeint's controller on
/// rtol/atol), restarted at every sample like dopri5, with ∂f/∂x from the dual-number model
/// and ∂f/∂t from the slope of the inputs. The method is L-stable: a stiff mode does not
/// limit its step, only the accuracy asked for (and the sample interval) does.
template <class Observer>
SimulationStatus march_samples_stiff(StiffNetworkSystem& stiff, const InputChannels& inputs, std::size_t start,
                                     std::size_t last, std::vector<double>& x, const SimulationSettings& settings,
                                     SimulationBuffers& buffers, Observer&& observer) {
    namespace odeint = boost::numeric::odeint;
    const auto system = stiff.odeint_system();
    // A fresh controller per simulation: its step-size history must not leak from one
    // simulation (or thread) into the next.
    auto stepper = odeint::make_controlled(settings.atol, settings.rtol, buffers.stiff.rosenbrock4);
    UblasVector& state = buffers.stiff.state;
    state.resize(x.size(), false);
    std::copy(x.begin(), x.end(), state.begin());
    const auto enter_interval = [&](std::size_t i) { stiff.enter_interval(i); };
    const auto try_step = [&](double& t, double& dt) {
        StepAttempt attempt;
        attempt.accepted = stepper.try_step(system, state, t, dt) != odeint::fail;
        if (!attempt.accepted) {
            if (!stiff.start_finite()) attempt.status = SimulationStatus::not_finite;
            return attempt;
        }
        std::copy(state.begin(), state.end(), x.begin());
        state_is_sane(x, attempt.status);
        return attempt;
    };
    const auto look = [&](std::size_t i) {
        return observer(i, x, buffers.u) ? SimulationStatus::ok : SimulationStatus::stopped_by_observer;
    };
    return march_over_samples(
        start, last, ControlledSteps(inputs.time(), start, last, settings.max_steps, enter_interval, try_step),
        sample_hooks(inputs, buffers.u, SystemMemory<StiffNetworkSystem, std::vector<double>>{stiff, x}, look));
}

/// The march of simulate_samples for sdirk3: fixed implicit steps (sim/sdirk3.hpp) of the
/// sample interval, split by max_step, with `checked` = every state tested after each
/// interval. With `s` (n × directions, set up by Sdirk3::bind_sensitivities) the steps carry
/// the sensitivities too; `memory` restarts and samples the elements with memory.
template <class Memory, class Look>
SimulationStatus march_sdirk3(Sdirk3& stepper, const InputChannels& inputs, std::size_t start, std::size_t last,
                              double* x, std::size_t n, double* s, std::size_t s_size, double max_step,
                              std::vector<double>& u, Memory memory, Look look) {
    stepper.begin(x);
    const auto cross = [&](std::size_t i) {
        const SimulationStatus status = stepper.cross(inputs.time(), i, max_step, x, s);
        if (status != SimulationStatus::ok) return status;
        for (std::size_t k = 0; k < n; ++k) {
            if (!std::isfinite(x[k])) return SimulationStatus::not_finite;
            if (std::abs(x[k]) > kDivergenceLimit) return SimulationStatus::diverged;
        }
        for (std::size_t k = 0; k < s_size; ++k)
            if (!std::isfinite(s[k])) return SimulationStatus::not_finite;
        return SimulationStatus::ok;
    };
    return march_over_samples(start, last, cross, sample_hooks(inputs, u, std::move(memory), std::move(look)));
}

/// Integrates the model from sample `start` (state x at time[start]) to sample `last`,
/// calling `observer(i, x, u)` at every sample i in (start, last] with u the inputs at
/// time[i]. The observer returns false to stop early.
template <class Observer>
SimulationStatus simulate_samples(NetworkModel<double>& model, const InputChannels& inputs,
                                  std::size_t start, std::size_t last, std::vector<double>& x,
                                  const SimulationSettings& settings, SimulationBuffers& buffers,
                                  Observer&& observer) {
    buffers.u.resize(inputs.count());
    if (settings.method == IntegrationMethod::sdirk3) {
        Sdirk3& stepper = buffers.sdirk3;
        stepper.bind(model, inputs);
        const std::size_t rhs = stepper.rhs_evaluations, jacobians = stepper.jacobian_evaluations;
        struct Memory {
            Sdirk3& stepper;
            const std::vector<double>& x;
            void restart(const std::vector<double>& u) { stepper.restart_sampling(x.data(), u.data()); }
            void sample(double t, const std::vector<double>& u) { stepper.sample(t, x.data(), u.data()); }
        };
        const auto look = [&](std::size_t i) {
            return observer(i, x, buffers.u) ? SimulationStatus::ok : SimulationStatus::stopped_by_observer;
        };
        const SimulationStatus status = march_sdirk3(stepper, inputs, start, last, x.data(), x.size(), nullptr, 0,
                                                     settings.max_step, buffers.u, Memory{stepper, x}, look);
        buffers.rhs_evaluations += stepper.rhs_evaluations - rhs;
        buffers.jacobian_evaluations += stepper.jacobian_evaluations - jacobians;
        return status;
    }
    if (integration_method_row(settings.method).uses_jacobian) {
        StiffNetworkSystem stiff(model, inputs, buffers.u, buffers.stiff);
        const SimulationStatus status =
            march_samples_stiff(stiff, inputs, start, last, x, settings, buffers, std::forward<Observer>(observer));
        buffers.rhs_evaluations += stiff.evaluations;
        buffers.jacobian_evaluations += stiff.jacobians;
        return status;
    }
    const auto odeint_march = [&] {
        NetworkSystem system(model, inputs, buffers.u);
        const SimulationStatus status = march_samples(system, inputs, start, last, x, x.size(), settings, buffers,
                                                      std::forward<Observer>(observer));
        buffers.rhs_evaluations += system.evaluations;
        return status;
    };
    if (!takes_fixed_steps(settings.method)) return odeint_march();
    // Small models (every preset): RK4 over a fixed-size state, the same arithmetic.
    const auto fixed = [&]<std::size_t N>(std::integral_constant<std::size_t, N>) {
        return march_fixed_state_rk4<N>(model, inputs, start, last, x, settings.max_step, buffers.u, buffers.u_stages,
                                        buffers.rhs_evaluations, observer);
    };
    return dispatch_state_size(x.size(), fixed, odeint_march);
}

}  // namespace tvid

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
#include "tvid/sim/simulation_settings.hpp"
#include "tvid/sim/simulation_status.hpp"
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
    // Running totals over every simulate_samples call, for benchmarks.
    std::size_t rhs_evaluations = 0;       ///< f(x, u) with double
    std::size_t jacobian_evaluations = 0;  ///< ∂f/∂x (rosenbrock4)
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
template <class System, class Observer>
SimulationStatus march_samples(System& system, const InputChannels& inputs, std::size_t start, std::size_t last,
                               std::vector<double>& x, std::size_t checked, const SimulationSettings& settings,
                               SimulationBuffers& buffers, Observer&& observer) {
    namespace odeint = boost::numeric::odeint;
    const std::vector<double>& time = inputs.time();
    buffers.u.resize(inputs.count());
    std::size_t hint = start;
    SimulationStatus status = SimulationStatus::ok;
    if (settings.method == IntegrationMethod::rk4) {
        for (std::size_t i = start; i < last; ++i) {
            const double t0 = time[i], h = time[i + 1] - t0;
            int substeps = 1;
            if (settings.max_step > 0.0 && h > settings.max_step)
                substeps = static_cast<int>(std::ceil(h / settings.max_step - 1e-9));
            const double dt = h / substeps;
            for (int s = 0; s < substeps; ++s)
                buffers.rk4.do_step(std::ref(system), x, t0 + s * dt, dt);
            if (!state_is_sane(x, status, checked)) return status;
            inputs.at(time[i + 1], hint, buffers.u.data());
            if (!observer(i + 1, x, buffers.u)) return SimulationStatus::stopped_by_observer;
        }
        return status;
    }
    // Adaptive Dormand–Prince, restarted at every sample so the kinks of the linearly
    // interpolated input fall on step boundaries. (A system without a Jacobian, such as
    // the augmented sensitivity system, also marches this way under rosenbrock4.)
    auto stepper = odeint::make_controlled(settings.atol, settings.rtol, buffers.dopri5);
    std::size_t steps = 0;
    double dt = (time[std::min(start + 1, last)] - time[start]);
    for (std::size_t i = start; i < last; ++i) {
        double t = time[i];
        const double t_end = time[i + 1];
        while (t < t_end) {
            if (++steps > settings.max_steps) return SimulationStatus::step_budget_exceeded;
            dt = std::min(dt, t_end - t);
            const auto result = stepper.try_step(std::ref(system), x, t, dt);
            if (result == odeint::fail) {
                if (!(dt > 1e-14 * (1.0 + std::abs(t)))) return SimulationStatus::step_budget_exceeded;
                continue;
            }
            if (!state_is_sane(x, status, checked)) return status;
            if (t_end - t < 1e-12 * (1.0 + std::abs(t_end))) t = t_end;
        }
        inputs.at(time[i + 1], hint, buffers.u.data());
        if (!observer(i + 1, x, buffers.u)) return SimulationStatus::stopped_by_observer;
    }
    return status;
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
    const std::vector<double>& time = inputs.time();
    const auto system = stiff.odeint_system();
    // A fresh controller per simulation: its step-size history must not leak from one
    // simulation (or thread) into the next.
    auto stepper = odeint::make_controlled(settings.atol, settings.rtol, buffers.stiff.rosenbrock4);
    UblasVector& state = buffers.stiff.state;
    state.resize(x.size(), false);
    std::copy(x.begin(), x.end(), state.begin());
    std::size_t hint = start, steps = 0;
    SimulationStatus status = SimulationStatus::ok;
    double dt = (time[std::min(start + 1, last)] - time[start]);
    for (std::size_t i = start; i < last; ++i) {
        stiff.enter_interval(i);
        double t = time[i];
        const double t_end = time[i + 1];
        while (t < t_end) {
            if (++steps > settings.max_steps) return SimulationStatus::step_budget_exceeded;
            dt = std::min(dt, t_end - t);
            const auto result = stepper.try_step(system, state, t, dt);
            if (result == odeint::fail) {
                if (!stiff.start_finite()) return SimulationStatus::not_finite;
                if (!(dt > 1e-14 * (1.0 + std::abs(t)))) return SimulationStatus::step_budget_exceeded;
                continue;
            }
            std::copy(state.begin(), state.end(), x.begin());
            if (!state_is_sane(x, status)) return status;
            if (t_end - t < 1e-12 * (1.0 + std::abs(t_end))) t = t_end;
        }
        inputs.at(time[i + 1], hint, buffers.u.data());
        if (!observer(i + 1, x, buffers.u)) return SimulationStatus::stopped_by_observer;
    }
    return status;
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
    if (settings.method == IntegrationMethod::rosenbrock4) {
        StiffNetworkSystem stiff(model, inputs, buffers.u, buffers.stiff);
        const SimulationStatus status =
            march_samples_stiff(stiff, inputs, start, last, x, settings, buffers, std::forward<Observer>(observer));
        buffers.rhs_evaluations += stiff.evaluations;
        buffers.jacobian_evaluations += stiff.jacobians;
        return status;
    }
    if (settings.method == IntegrationMethod::rk4 && x.size() <= kMaxFixedState && x.size() % 2 == 0) {
        // Small models (every preset): RK4 over a fixed-size state, the same arithmetic.
        const auto fixed = [&]<std::size_t N>(std::integral_constant<std::size_t, N>) {
            return march_fixed_state_rk4<N>(model, inputs, start, last, x, settings.max_step, buffers.u,
                                            buffers.u_stages, buffers.rhs_evaluations, observer);
        };
        switch (x.size()) {
            case 2: return fixed(std::integral_constant<std::size_t, 2>{});
            case 4: return fixed(std::integral_constant<std::size_t, 4>{});
            case 6: return fixed(std::integral_constant<std::size_t, 6>{});
            case 8: return fixed(std::integral_constant<std::size_t, 8>{});
            case 10: return fixed(std::integral_constant<std::size_t, 10>{});
            case 12: return fixed(std::integral_constant<std::size_t, 12>{});
            case 14: return fixed(std::integral_constant<std::size_t, 14>{});
            case 16: return fixed(std::integral_constant<std::size_t, 16>{});
            default: break;
        }
    }
    NetworkSystem system(model, inputs, buffers.u);
    const SimulationStatus status = march_samples(system, inputs, start, last, x, x.size(), settings, buffers,
                                                  std::forward<Observer>(observer));
    buffers.rhs_evaluations += system.evaluations;
    return status;
}

}  // namespace tvid

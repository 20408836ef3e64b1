#pragma once
// Simulation of a network over a span of samples with Boost.Odeint: fixed-step RK4
// (the sampling interval, as seed 001 does, optionally split into substeps) or adaptive
// Dormand–Prince 5(4) with rtol/atol. The observer sees the state at every sample.
// A simulation that produces NaN/inf, grows without bound, or exceeds its step budget
// stops with a status instead of throwing.

#include <boost/numeric/odeint.hpp>
#include <cmath>
#include <cstddef>
#include <vector>

#include "tvid/experiment/experiment.hpp"
#include "tvid/model/network_model.hpp"
#include "tvid/sim/input_channels.hpp"

namespace tvid {

enum class SimulationStatus { ok, not_finite, diverged, step_budget_exceeded, stopped_by_observer };

const char* to_string(SimulationStatus s);

/// |θ| or |ω| beyond this is taken as a diverging simulation.
inline constexpr double kDivergenceLimit = 1e12;

/// The odeint system: dx/dt = f(x, u(t)) with inputs interpolated at t.
class NetworkSystem {
public:
    NetworkSystem(NetworkModel<double>& model, const InputChannels& inputs, std::vector<double>& u)
        : model_(&model), inputs_(&inputs), u_(&u) {}
    void operator()(const std::vector<double>& x, std::vector<double>& dxdt, double t) {
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
struct SimulationBuffers {
    std::vector<double> u;
    boost::numeric::odeint::runge_kutta4<std::vector<double>> rk4;
    using Dopri5 = boost::numeric::odeint::runge_kutta_dopri5<std::vector<double>>;
    Dopri5 dopri5;
};

inline bool state_is_sane(const std::vector<double>& x, SimulationStatus& status) {
    for (double v : x) {
        if (!std::isfinite(v)) { status = SimulationStatus::not_finite; return false; }
        if (std::abs(v) > kDivergenceLimit) { status = SimulationStatus::diverged; return false; }
    }
    return true;
}

/// Integrates from sample `start` (state x at time[start]) to sample `last`, calling
/// `observer(i, x, u)` at every sample i in (start, last] with u the inputs at time[i].
/// The observer returns false to stop early.
template <class Observer>
SimulationStatus simulate_samples(NetworkModel<double>& model, const InputChannels& inputs,
                                  std::size_t start, std::size_t last, std::vector<double>& x,
                                  const SimulationSettings& settings, SimulationBuffers& buffers,
                                  Observer&& observer) {
    namespace odeint = boost::numeric::odeint;
    const std::vector<double>& time = inputs.time();
    buffers.u.resize(inputs.count());
    NetworkSystem system(model, inputs, buffers.u);
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
            if (!state_is_sane(x, status)) return status;
            inputs.at(time[i + 1], hint, buffers.u.data());
            if (!observer(i + 1, x, buffers.u)) return SimulationStatus::stopped_by_observer;
        }
        return status;
    }
    // Adaptive Dormand–Prince, restarted at every sample so the kinks of the linearly
    // interpolated input fall on step boundaries.
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
            if (!state_is_sane(x, status)) return status;
            if (t_end - t < 1e-12 * (1.0 + std::abs(t_end))) t = t_end;
        }
        inputs.at(time[i + 1], hint, buffers.u.data());
        if (!observer(i + 1, x, buffers.u)) return SimulationStatus::stopped_by_observer;
    }
    return status;
}

}  // namespace tvid

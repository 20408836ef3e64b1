#pragma once
// The classical RK4 of simulate_samples for a model with a small state, written out over
// a fixed-size state on the stack (std::array<double, N>) instead of odeint's stepper over
// std::vector: the same stages, coefficients and order of operations as odeint's
// runge_kutta4 (x + dt/2·k1, x + dt/2·k2, x + dt·k3, x + dt/6·k1 + dt/3·k2 + dt/3·k3 + dt/6·k4),
// without the resizing checks and loops over run-time sizes. The inputs at the stage times
// are not searched for at every right-hand side: at the sampling step they are the
// samples and the precomputed sample midpoints (InputChannels::midpoint); with substeps,
// the interval is known and only the interpolation weight changes.

#include <array>
#include <cmath>
#include <cstddef>
#include <vector>

#include "tvid/model/network_model.hpp"
#include "tvid/model/packed_dual.hpp"
#include "tvid/channels/input_channels.hpp"
#include "tvid/sim/observation_loops.hpp"
#include "tvid/sim/rk4_stages.hpp"
#include "tvid/sim/simulation_status.hpp"
#include "tvid/sim/state_size_dispatch.hpp"

namespace tvid {

/// The sane-state test of simulate.hpp (state_is_sane) on the fixed-size state.
template <std::size_t N>
bool fixed_state_is_sane(const std::array<double, N>& x, SimulationStatus& status) {
    for (std::size_t i = 0; i < N; ++i) {
        if (!std::isfinite(x[i])) { status = SimulationStatus::not_finite; return false; }
        if (std::abs(x[i]) > kDivergenceLimit) { status = SimulationStatus::diverged; return false; }
    }
    return true;
}

/// The same for a state with sensitivities: the values as above, the derivatives finite.
template <std::size_t N, int D>
bool fixed_state_is_sane(const std::array<PackedDual<D>, N>& x, SimulationStatus& status) {
    for (std::size_t i = 0; i < N; ++i) {
        if (!x[i].all_finite()) { status = SimulationStatus::not_finite; return false; }
        if (std::abs(x[i].value()) > kDivergenceLimit) { status = SimulationStatus::diverged; return false; }
    }
    return true;
}

/// RK4 over the fixed-size state x (scalar type T: double, or PackedDual for the
/// sensitivities) from sample `start` to `last`, `substeps` per sample interval from
/// `max_step` (0: one step per interval), calling observer(i, x, u) at every sample i in
/// (start, last] with u the inputs at time[i]; the observer returns false to stop.
/// Returns the status; `rhs` counts the right-hand sides.
template <std::size_t N, class T, class Observer>
SimulationStatus march_fixed_rk4(NetworkModel<T>& model, const InputChannels& inputs, std::size_t start,
                                 std::size_t last, std::array<T, N>& x, double max_step, std::vector<double>& u,
                                 std::vector<double>& u_stage, std::size_t& rhs, Observer&& observer) {
    u.resize(inputs.count());
    Rk4StageInputs in(inputs, u_stage, start);
    Rk4Stages<T, N> k;
    const auto step = [&](const FixedStep& s) {
        const double dt = s.dt;
        in.read(s, true);
        model.derivative(x.data(), in.u0, k.k1.data());
        rk4_from_first_stage(model, x, k, in, 0.5 * dt, dt, (1.0 / 6.0) * dt, (1.0 / 3.0) * dt);
        rhs += 4;
    };
    const auto check = [&] {
        SimulationStatus status = SimulationStatus::ok;
        fixed_state_is_sane(x, status);
        return status;
    };
    const auto look = [&](std::size_t i) {
        return observer(i, x, u) ? SimulationStatus::ok : SimulationStatus::stopped_by_observer;
    };
    return march_over_samples(start, last, FixedSubsteps(inputs.time(), max_step, step, check),
                              sample_hooks(inputs, u, ModelMemory<NetworkModel<T>, T>{model, x.data()}, look));
}

/// march_fixed_rk4 for a double state held in a vector (N = x.size()), calling
/// observer(i, x, u) with that vector, as march_samples does.
template <std::size_t N, class Observer>
SimulationStatus march_fixed_state_rk4(NetworkModel<double>& model, const InputChannels& inputs, std::size_t start,
                                       std::size_t last, std::vector<double>& x_out, double max_step,
                                       std::vector<double>& u, std::vector<double>& u_stage, std::size_t& rhs,
                                       Observer&& observer) {
    std::array<double, N> x;
    for (std::size_t j = 0; j < N; ++j) x[j] = x_out[j];
    const auto copy_out = [&](std::size_t i, const std::array<double, N>& state, const std::vector<double>& inputs_now) {
        for (std::size_t j = 0; j < N; ++j) x_out[j] = state[j];
        return observer(i, x_out, inputs_now);
    };
    const SimulationStatus status = march_fixed_rk4<N>(model, inputs, start, last, x, max_step, u, u_stage, rhs, copy_out);
    if (status != SimulationStatus::ok && status != SimulationStatus::stopped_by_observer)
        for (std::size_t j = 0; j < N; ++j) x_out[j] = x[j];
    return status;
}

}  // namespace tvid

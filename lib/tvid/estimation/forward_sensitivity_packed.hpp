#pragma once
// The body of ForwardSensitivity::simulate_packed, included by the files that instantiate
// it (one per width D, so that the two compile side by side): the window simulated with
// every state a PackedDual<D>, the block's columns and the warm-up shooting's two
// directions carried through the fixed-step RK4.

#include <array>
#include <cmath>
#include <string>
#include <vector>

#include "tvid/estimation/forward_sensitivity.hpp"
#include "tvid/estimation/stable_step.hpp"
#include "tvid/sim/fixed_state_rk4.hpp"

namespace tvid {

/// After a shot warm-up: G = (θ_node(mid), θ_node(first)) − measured gives
/// d(a, s)/dp = −(∂G/∂(a, s))⁻¹ ∂G/∂p, and every state's derivative becomes the total
/// S_p + S_(a,s)·d(a,s)/dp (directions cols and cols + 1 are a and s, zeroed after). The
/// slopes are kept in `slopes` (a, s per column). False when the shooting is singular.
template <std::size_t N, int D>
bool correct_for_shooting(std::array<PackedDual<D>, N>& x, const PackedDual<D>& at_mid, std::size_t node,
                          std::size_t cols, std::vector<double>& slopes) {
    const auto a_dir = static_cast<int>(cols), s_dir = static_cast<int>(cols + 1);
    const PackedDual<D>& at_first = x[node];
    const ShootingSensitivity shooting(at_mid.derivative(a_dir), at_mid.derivative(s_dir),
                                       at_first.derivative(a_dir), at_first.derivative(s_dir));
    if (!shooting.regular()) return false;
    Pack<D> da(0.0), ds(0.0);
    for (std::size_t j = 0; j < cols; ++j) {
        const double mid_j = at_mid.derivative(static_cast<int>(j)), first_j = at_first.derivative(static_cast<int>(j));
        da.set(static_cast<int>(j), shooting.offset_slope(mid_j, first_j));
        ds.set(static_cast<int>(j), shooting.speed_slope(mid_j, first_j));
    }
    slopes.resize(2 * cols);
    for (std::size_t j = 0; j < cols; ++j) {
        slopes[2 * j] = da[static_cast<int>(j)];
        slopes[2 * j + 1] = ds[static_cast<int>(j)];
    }
    for (std::size_t i = 0; i < N; ++i) {
        const Pack<D>& row = x[i].derivatives();
        Pack<D> total = row + Pack<D>(row[a_dir]) * da + Pack<D>(row[s_dir]) * ds;
        total.set(a_dir, 0.0);
        total.set(s_dir, 0.0);
        x[i].set_derivatives(total);
    }
    return true;
}

template <std::size_t N, int D>
SimulationStatus ForwardSensitivity::simulate_packed(const double* free, const Window& w, std::size_t j0,
                                                     std::size_t j1, SensitivityWorkspace& ws, std::string* problem,
                                                     PackedObserver<D> on_scored, const SolvedStart* solved) const {
    using T = PackedDual<D>;
    PackedSensitivityModel<D>& dual = ws.packed<D>();
    const ProblemDefinition& def = problem_->definition();
    const std::size_t cols = j1 - j0, n = N / 2;
    // The plain start (equilibrium, or the warm-up shooting) and the Dual model for the
    // equilibrium's sensitivity, as the augmented path sets them.
    set_parameters(free, j0, j1, static_cast<int>(cols), ws);
    const InputChannels& inputs = *ws.plain->inputs;  // shifted by the candidate's delays
    const WindowStart start = window_start(w, ws, problem, solved);
    if (start.status != SimulationStatus::ok) return start.status;
    if (start.implicit_steps) {
        // Too stiff for RK4's substeps: sdirk3's steps (stable_step.hpp), which carry the
        // sensitivities on the augmented path, from this start; the outputs handed on as packs.
        const SolvedStart own{start, ws.plain->x_start, ws.plain->x, ws.plain->u0};
        std::array<T, 8> y_packed;
        const auto as_packs = [&](std::size_t i, const Dual* y) {
            for (std::size_t k = 0; k < def.measured.size(); ++k) {
                y_packed[k] = T(y[k].value());
                for (std::size_t j = 0; j < cols; ++j)
                    y_packed[k].set_derivative(static_cast<int>(j), y[k].derivative(static_cast<int>(j)));
            }
            return on_scored(i, y_packed.data());
        };
        return simulate_augmented(free, w, j0, j1, ws, problem, as_packs, &own);
    }

    // Parameters: the block's columns are directions 0 … cols−1; a shot warm-up's angle
    // offset a and speed s are directions cols and cols + 1.
    const std::vector<std::size_t>& index = problem_->free_indices();
    for (std::size_t i = 0; i < dual.params.size(); ++i) dual.params[i] = T(ws.plain->params[i]);
    for (std::size_t j = j0; j < j1; ++j) dual.params[index[j]] = T::variable(free[j], static_cast<int>(j - j0));
    dual.model.set_parameters(dual.params.data());
    std::array<T, N> x;
    for (std::size_t i = 0; i < N; ++i) x[i] = T(ws.plain->x_start[i]);
    Eigen::MatrixXd dtheta;
    if (!start_sensitivity(w, j0, j1, ws, dtheta, problem)) return SimulationStatus::not_finite;
    if (dtheta.size() > 0) {  // the angles' rows, or every state's for an estimated start
        for (std::size_t i = 0; i < static_cast<std::size_t>(dtheta.rows()); ++i)
            for (std::size_t j = 0; j < cols; ++j)
                x[i].set_derivative(static_cast<int>(j), dtheta(static_cast<Eigen::Index>(i), static_cast<Eigen::Index>(j)));
    }
    const auto a_dir = static_cast<int>(cols), s_dir = static_cast<int>(cols + 1);
    if (start.shot)
        for (std::size_t i = 0; i < n; ++i) {
            const double r = speed_ratio(ws.plain->x_start, n, start.node, i);  // through the gear ratios
            x[i].set_derivative(a_dir, r);      // ∂θ_i/∂a
            x[n + i].set_derivative(s_dir, r);  // ∂ω_i/∂s
        }

    std::array<T, 8> y_store;  // the outputs at a sample (at most 8 outputs take this path)
    const auto outputs = [&](std::size_t i, const std::array<T, N>& state, const std::vector<double>& u) {
        for (std::size_t k = 0; k < def.measured.size(); ++k)
            y_store[k] = dual.model.output(static_cast<std::size_t>(def.output_indices[k]), state.data(), u.data());
        return on_scored(i, y_store.data());
    };
    std::size_t& rhs = ws.buffers.rhs_evaluations;
    std::size_t from = w.start;
    if (problem_->warms_up(w)) {
        // The warm-up, watching the encoder node's angle at the shooting's samples.
        T at_mid;
        const auto watch = [&](std::size_t i, const std::array<T, N>& state, const std::vector<double>&) {
            if (i == start.mid) at_mid = state[start.node];
            return !ws.plain->stop_requested();
        };
        const SimulationStatus status = march_fixed_rk4<N>(dual.model, inputs, w.start, w.first, x, window_max_step(def, w, *ws.plain),
                                                           ws.buffers.u, ws.buffers.u_stages, rhs, watch);
        if (status != SimulationStatus::ok) {
            if (problem) *problem = std::string("warm-up simulation ") + to_string(status);
            return status;
        }
        if (start.shot && !correct_for_shooting<N, D>(x, at_mid, start.node, cols, ws.start_slopes)) {
            if (problem) *problem = ShootingSensitivity::kSingular;
            return SimulationStatus::not_finite;
        }
        // After a warm-up the first sample is a prediction too: score it.
        std::size_t hint = w.first;
        inputs.at(inputs.time()[w.first], hint, ws.buffers.u.data());
        if (!outputs(w.first, x, ws.buffers.u)) return SimulationStatus::stopped_by_observer;
        from = w.first;
    }
    const auto scored = [&](std::size_t i, const std::array<T, N>& state, const std::vector<double>& u) {
        if (ws.plain->stop_requested()) return false;
        return i < w.first ? true : outputs(i, state, u);
    };
    const SimulationStatus status = march_fixed_rk4<N>(dual.model, inputs, from, w.last, x, window_max_step(def, w, *ws.plain),
                                                       ws.buffers.u, ws.buffers.u_stages, rhs, scored);
    if (status != SimulationStatus::ok && problem) *problem = std::string("simulation ") + to_string(status);
    return status;
}

}  // namespace tvid

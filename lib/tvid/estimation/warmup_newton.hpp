#pragma once
// The warm-up shooting by Newton's method with the exact Jacobian of the miss (fixed-step
// RK4, a state of N values): the common angle offset a and speed s added to a measured
// start so that the encoder's node meets the measured crank angle at the warm-up's middle
// sample and at the window's first. A simulation of the warm-up that carries ∂x/∂a and
// ∂x/∂s (PackedDual directions 0 and 1) gives the Jacobian, so Newton converges
// quadratically. The measured start misses by up to tenths of a radian, so:
//  1. Newton on a coarse simulation (one RK4 step per sample where the experiment asks for
//     substeps) from the measured start, to within 1e-7 rad: cheap, and only a guess, never
//     the result (given up if it fails, e.g. unstable for a stiff candidate);
//  2. from there a Newton step with the full simulation and its tangents;
//  3. chord steps with that Jacobian on plain simulations until the miss is below the
//     tolerance. Typically one tangent and one or two plain full simulations; the last
//     leaves the state at w.first (tangent and plain runs compute the same values).
// With a guess from nearby parameters (ws.shooting_guesses: a least-squares solver's trial
// point near the point of its last Jacobian), steps 1–3 are first replaced by chord steps
// from the guess on plain simulations (1'); only when those do not converge are steps 1–3
// done as without a guess.
//
// Included by window_start.cpp only.

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <vector>

#include "tvid/estimation/stable_step.hpp"
#include "tvid/estimation/window_start.hpp"
#include "tvid/sim/fixed_state_rk4.hpp"

namespace tvid {

template <std::size_t N>
class WarmupNewton {
public:
    WarmupNewton(const ProblemDefinition& d, const Window& w, ProblemWorkspace& ws, WindowStart& start)
        : d_(d), w_(w), ws_(ws), start_(start), node_(static_cast<std::size_t>(d.angle_node)),
          mid_(w.start + (w.first - w.start) / 2), angle_(d.crank_angle),
          tolerance_(1e-12 + 1e-15 * std::abs(d.crank_angle[w.first])), max_step_(window_max_step(d, w, ws)) {}

    /// Solves the shooting; leaves ws.x at the state at w.first.
    SimulationStatus solve() {
        const std::vector<double>& p = ws_.model.parameters();
        for (std::size_t i = 0; i < p.size(); ++i) ws_.tangent_params[i] = T(p[i]);
        ws_.tangent_model.set_parameters(ws_.tangent_params.data());
        ws_.x0 = ws_.x;
        a_ = 0.0, s_ = ws_.x0[n + node_];
        start_.shot = false;
        ws_.x_start = ws_.x;
        if (from_guesses() != GuessOutcome::not_solved) return status_;
        coarse_guess();
        // 2. Newton with the full simulation's tangents.
        if (!tangent_miss(a_, s_, max_step_)) return status_;
        return finish_from_tangents();
    }

private:
    using T = PackedDual<2>;
    static constexpr std::size_t n = N / 2;

    // The rigid motion through the gear ratios: node i turns r_i times the encoder's node.
    double r(std::size_t i) const { return speed_ratio(ws_.x0, n, node_, i); }
    double start_state(double a, double s, std::size_t i) const { return i < n ? ws_.x0[i] + a * r(i) : s * r(i - n); }
    bool below(double limit) const { return std::abs(e_[0]) < limit && std::abs(e_[1]) < limit; }
    bool miss_is_finite() const {
        return status_ == SimulationStatus::ok && std::isfinite(e_[0]) && std::isfinite(e_[1]);
    }
    void solution_at_last_simulation() {
        start_.offset = simulated_a_;
        start_.speed = simulated_s_;
    }

    // The miss from (a, s) and its Jacobian, from a simulation with tangents (max_step 0:
    // one RK4 step per sample, the coarse simulation).
    bool tangent_miss(double a, double s, double max_step) {
        simulated_a_ = a, simulated_s_ = s;
        std::array<T, N> x;
        for (std::size_t i = 0; i < N; ++i) {
            x[i] = T(start_state(a, s, i));
            x[i].set_derivative(i < n ? 0 : 1, r(i < n ? i : i - n));  // ∂θ_i/∂a, ∂ω_i/∂s
            ws_.x_start[i] = x[i].value();
        }
        T at_mid;
        const auto watch = [&](std::size_t i, const std::array<T, N>& state, const std::vector<double>&) {
            if (i == mid_) at_mid = state[node_];
            return !ws_.stop_requested();
        };
        status_ = march_fixed_rk4<N>(ws_.tangent_model, *ws_.inputs, w_.start, w_.first, x, max_step, ws_.buffers.u,
                                     ws_.buffers.u_stages, ws_.buffers.rhs_evaluations, watch);
        for (std::size_t i = 0; i < N; ++i) ws_.x[i] = x[i].value();
        e_[0] = at_mid.value() - angle_[mid_];
        e_[1] = x[node_].value() - angle_[w_.first];
        jac_[0][0] = at_mid.derivative(0), jac_[0][1] = at_mid.derivative(1);
        jac_[1][0] = x[node_].derivative(0), jac_[1][1] = x[node_].derivative(1);
        if (max_step == max_step_) start_.miss_jacobian = jac_;
        return miss_is_finite();
    }

    // The miss from (a, s) by a plain simulation.
    bool plain_miss(double a, double s) {
        simulated_a_ = a, simulated_s_ = s;
        std::array<double, N> x;
        for (std::size_t i = 0; i < N; ++i) x[i] = ws_.x_start[i] = start_state(a, s, i);
        double at_mid = 0.0;
        const auto watch = [&](std::size_t i, const std::array<double, N>& state, const std::vector<double>&) {
            if (i == mid_) at_mid = state[node_];
            return !ws_.stop_requested();
        };
        status_ = march_fixed_rk4<N>(ws_.model, *ws_.inputs, w_.start, w_.first, x, max_step_,
                                     ws_.buffers.u, ws_.buffers.u_stages, ws_.buffers.rhs_evaluations, watch);
        for (std::size_t i = 0; i < N; ++i) ws_.x[i] = x[i];
        e_[0] = at_mid - angle_[mid_];
        e_[1] = x[node_] - angle_[w_.first];
        return miss_is_finite();
    }

    // One Newton (or chord) step on (a, s) with the Jacobian held.
    bool newton_step(double& a, double& s) const {
        const double det = jac_[0][0] * jac_[1][1] - jac_[0][1] * jac_[1][0];
        if (!std::isfinite(det) || det == 0.0) return false;
        a -= (jac_[1][1] * e_[0] - jac_[0][1] * e_[1]) / det;
        s -= (-jac_[1][0] * e_[0] + jac_[0][0] * e_[1]) / det;
        return std::isfinite(a) && std::isfinite(s);
    }

    // Broyden's update: the Jacobian takes the secant of the last step.
    void broyden_update(const double last_e[2], const double step[2]) {
        const double de[2] = {e_[0] - last_e[0], e_[1] - last_e[1]};
        const double norm2 = step[0] * step[0] + step[1] * step[1];
        for (int row = 0; row < 2 && norm2 > 0; ++row) {
            const double f = (de[row] - jac_[row][0] * step[0] - jac_[row][1] * step[1]) / norm2;
            jac_[row][0] += f * step[0], jac_[row][1] += f * step[1];
        }
    }

    // 1'. From a guess at nearby parameters: chord steps with the Jacobian of the miss
    // computed there, on plain simulations, while each cuts the miss at least tenfold (the
    // map differs little between nearby parameters: mostly the rigid motion's a + s·t).
    // Otherwise (a, s) are reset to the measured start.
    enum class GuessOutcome { solved, stopped, not_solved };
    GuessOutcome from_guesses() {
        for (const ShootingGuess& g : ws_.shooting_guesses) {
            if (g.start != w_.start || g.first != w_.first || !std::isfinite(g.offset) || !std::isfinite(g.speed))
                continue;
            a_ = g.offset, s_ = g.speed;
            jac_ = g.miss_jacobian;
            double last_miss = std::numeric_limits<double>::infinity(), last_e[2] = {0, 0}, step[2] = {0, 0};
            for (int it = 0; it < 6 && plain_miss(a_, s_); ++it) {
                const double miss = std::max(std::abs(e_[0]), std::abs(e_[1]));
                if (it > 0) broyden_update(last_e, step);
                if (below(tolerance_)) {
                    start_.shot = true;
                    start_.miss_jacobian = jac_;
                    solution_at_last_simulation();
                    return GuessOutcome::solved;
                }
                if (!(miss < 0.1 * last_miss)) break;
                last_miss = miss, last_e[0] = e_[0], last_e[1] = e_[1];
                const double a_before = a_, s_before = s_;
                if (!newton_step(a_, s_)) break;
                step[0] = a_ - a_before, step[1] = s_ - s_before;
            }
            if (ws_.stop_requested()) return GuessOutcome::stopped;
            a_ = 0.0, s_ = ws_.x0[n + node_];  // too far, or failed there: as without a guess
            status_ = SimulationStatus::ok;
            break;
        }
        return GuessOutcome::not_solved;
    }

    // 1. The guess from the coarse simulation, taken when it gets within 1e-7 rad.
    void coarse_guess() {
        if (!(max_step_ > 0.0)) return;
        constexpr double coarse_tolerance = 1e-7;
        double ca = a_, cs = s_;
        bool usable = false;
        for (int it = 0; it < 8; ++it) {
            if (!tangent_miss(ca, cs, 0.0)) break;
            if (below(coarse_tolerance)) {
                usable = true;
                break;
            }
            if (!newton_step(ca, cs)) break;
        }
        if (usable) a_ = ca, s_ = cs;
        status_ = SimulationStatus::ok;
    }

    // 2. and 3., from a full simulation with tangents just run at (a, s).
    SimulationStatus finish_from_tangents() {
        start_.shot = below(tolerance_);
        if (!start_.shot && !newton_step(a_, s_)) return status_;  // no handle on the rigid motion: keep the start so far
        start_.shot = true;
        for (int it = 0; it < 8 && !below(tolerance_); ++it) {
            if (!plain_miss(a_, s_)) break;
            if (below(tolerance_) || !newton_step(a_, s_)) break;
            if (it == 7) plain_miss(a_, s_);
        }
        solution_at_last_simulation();
        return status_;  // ws.x: the state at w.first
    }

    const ProblemDefinition& d_;
    const Window& w_;
    ProblemWorkspace& ws_;
    WindowStart& start_;
    const std::size_t node_, mid_;
    const std::vector<double>& angle_;
    const double tolerance_;
    const double max_step_;  // the window's step at these parameters (stable_step.hpp)
    SimulationStatus status_ = SimulationStatus::ok;
    double e_[2] = {0, 0};
    MissJacobian jac_{};
    double a_ = 0.0, s_ = 0.0;
    double simulated_a_ = 0.0, simulated_s_ = 0.0;  // the start of the last simulation: where ws.x comes from
};

}  // namespace tvid

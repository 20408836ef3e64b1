#include "tvid/estimation/window_start.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <type_traits>

#include "tvid/model/equilibrium.hpp"
#include "tvid/model/steady_motion.hpp"
#include "tvid/sim/fixed_state_rk4.hpp"
#include "tvid/sim/state_size_dispatch.hpp"

namespace tvid {

double speed_ratio(const std::vector<double>& x, std::size_t n, std::size_t node, std::size_t i) {
    const double reference = x[n + node];
    if (!(reference != 0.0) || !std::isfinite(reference)) return 1.0;
    const double r = x[n + i] / reference;
    return std::isfinite(r) ? r : 1.0;
}

bool WindowStarts::initial_state(const Window& w, ProblemWorkspace& ws, std::string* problem) const {
    const std::size_t n = ws.model.node_count();
    const std::size_t start = w.start;
    std::size_t hint = start;
    ws.inputs->at(d_->inputs.time()[start], hint, ws.u0.data());
    std::fill(ws.x.begin(), ws.x.end(), 0.0);
    switch (d_->initial_state) {
        case InitialStateKind::rest: return true;
        case InitialStateKind::measured: {
            // Every node untwisted at the measured crank angle, turning at the measured
            // speed, both through the gear ratios (nodes no element joins keep them as they are).
            const auto out = static_cast<std::size_t>(d_->initial_speed_output);
            const double speed = (*ws.measured[out])[start];
            const int speed_node = d_->network.outputs[static_cast<std::size_t>(d_->output_indices[out])].node;
            const RigidMotion rigid = rigid_motion(d_->network, ws.model.parameters(), speed_node);
            if (!rigid.problem.empty()) {
                if (problem) *problem = rigid.problem;
                return false;
            }
            const auto ratio = [&](std::size_t i) { return rigid.tied[i] ? rigid.ratio[i] : 1.0; };
            const double angle = d_->crank_angle.empty() ? 0.0 : d_->crank_angle[start];
            const double angle_ratio = d_->angle_node >= 0 ? ratio(static_cast<std::size_t>(d_->angle_node)) : 1.0;
            for (std::size_t i = 0; i < n; ++i) {
                ws.x[i] = ratio(i) == angle_ratio ? angle : ratio(i) / angle_ratio * angle;
                ws.x[n + i] = ratio(i) * speed;
            }
            return true;
        }
        case InitialStateKind::steady: {
            // The line in steady rotation at the node's (mean) speed under the mean inputs
            // of the averaged samples, which ws.u0 keeps (the start's sensitivity reads them).
            const SteadyStartSpec& s = d_->steady;
            const std::size_t count = d_->inputs.samples();
            std::size_t end = s.samples > 0 ? start + s.samples : w.first > start ? w.first : start + 50;
            end = std::min(std::max(end, start + 1), count);
            const double m = static_cast<double>(end - start);
            for (std::size_t k = 0; k < ws.inputs->count(); ++k) {
                double sum = 0.0;
                for (std::size_t i = start; i < end; ++i) sum += ws.inputs->value(k, i);
                ws.u0[k] = sum / m;
            }
            // The speed column as its channel reads it (ProblemDefinition::steady_speed_input).
            double speed = s.speed;
            const auto column = [&](std::size_t i) {
                if (d_->steady_speed_input >= 0) return ws.inputs->value(static_cast<std::size_t>(d_->steady_speed_input), i);
                if (d_->steady_speed_output >= 0) return (*ws.measured[static_cast<std::size_t>(d_->steady_speed_output)])[i];
                return d_->steady_speed[i];
            };
            if (d_->steady_speed_input >= 0 || d_->steady_speed_output >= 0 || !d_->steady_speed.empty()) {
                double sum = 0.0;
                for (std::size_t i = start; i < end; ++i) sum += column(i);
                speed = sum / m;
            }
            const double angle = !d_->crank_angle.empty() && d_->angle_node == s.node ? d_->crank_angle[start] : 0.0;
            const SteadyMotion steady = solve_steady_motion(ws.model, ws.u0.data(), s.node, speed, angle);
            if (!steady.found) {
                if (problem) *problem = "no steady motion: " + steady.problem;
                return false;
            }
            std::copy(steady.x.begin(), steady.x.end(), ws.x.begin());
            return true;
        }
        case InitialStateKind::equilibrium: {
            // Yoshida & Takamatsu eq. 18: θ(t1) = θ̄ with F(θ̄, 0) balancing the input at t1, θ'(t1) = 0.
            EquilibriumResult eq = solve_equilibrium(ws.model, ws.u0.data());
            if (!eq.found) {
                if (problem) *problem = "no static equilibrium: " + eq.problem;
                return false;
            }
            for (std::size_t i = 0; i < n; ++i) ws.x[i] = eq.theta[i];
            return true;
        }
    }
    return false;
}

template <std::size_t N>
SimulationStatus WindowStarts::shoot_warmup_newton(const Window& w, ProblemWorkspace& ws, WindowStart& start) const {
    // As shoot_warmup, with the exact Jacobian of the miss: a simulation of the warm-up that
    // carries ∂x/∂a and ∂x/∂s (PackedDual directions 0 and 1) gives it, so Newton's method
    // converges quadratically. The measured start misses by up to tenths of a radian, so:
    //  1. Newton on a coarse simulation (one RK4 step per sample where the experiment asks
    //     for substeps) from the measured start, to within 1e-7 rad: cheap, and only a
    //     guess, never the result (given up if it fails, e.g. unstable for a stiff candidate);
    //  2. from there a Newton step with the full simulation and its tangents;
    //  3. chord steps with that Jacobian on plain simulations until the miss is below the
    //     tolerance. Typically one tangent and one or two plain full simulations; the last
    //     leaves the state at w.first (tangent and plain runs compute the same values).
    // With a guess from nearby parameters (ws.shooting_guesses: a least-squares solver's
    // trial point near the point of its last Jacobian), steps 1–3 are first replaced by
    // chord steps from the guess on plain simulations (1' below); only when those do not
    // converge are steps 1–3 done as without a guess.
    using T = PackedDual<2>;
    const std::size_t n = N / 2;
    const auto node = static_cast<std::size_t>(d_->angle_node);
    const std::size_t mid = w.start + (w.first - w.start) / 2;
    const std::vector<double>& angle = d_->crank_angle;
    const std::vector<double>& p = ws.model.parameters();
    for (std::size_t i = 0; i < p.size(); ++i) ws.tangent_params[i] = T(p[i]);
    ws.tangent_model.set_parameters(ws.tangent_params.data());
    ws.x0 = ws.x;
    SimulationStatus status = SimulationStatus::ok;
    double e[2];
    MissJacobian jac{};
    double simulated_a = 0.0, simulated_s = 0.0;  // the start of the last simulation: where ws.x comes from
    // The rigid motion through the gear ratios: node i turns r_i times the encoder's node.
    const auto r = [&](std::size_t i) { return speed_ratio(ws.x0, n, node, i); };
    auto start_state = [&](double a, double s, std::size_t i) { return i < n ? ws.x0[i] + a * r(i) : s * r(i - n); };
    auto tangent_miss = [&](double a, double s, double max_step) {
        simulated_a = a, simulated_s = s;
        std::array<T, N> x;
        for (std::size_t i = 0; i < N; ++i) {
            x[i] = T(start_state(a, s, i));
            x[i].set_derivative(i < n ? 0 : 1, r(i < n ? i : i - n));  // ∂θ_i/∂a, ∂ω_i/∂s
            ws.x_start[i] = x[i].value();
        }
        T at_mid;
        const auto watch = [&](std::size_t i, const std::array<T, N>& state, const std::vector<double>&) {
            if (i == mid) at_mid = state[node];
            return !ws.stop_requested();
        };
        status = march_fixed_rk4<N>(ws.tangent_model, *ws.inputs, w.start, w.first, x, max_step, ws.buffers.u,
                                    ws.buffers.u_stages, ws.buffers.rhs_evaluations, watch);
        for (std::size_t i = 0; i < N; ++i) ws.x[i] = x[i].value();
        e[0] = at_mid.value() - angle[mid];
        e[1] = x[node].value() - angle[w.first];
        jac[0][0] = at_mid.derivative(0), jac[0][1] = at_mid.derivative(1);
        jac[1][0] = x[node].derivative(0), jac[1][1] = x[node].derivative(1);
        if (max_step == d_->simulation.max_step) start.miss_jacobian = jac;
        return status == SimulationStatus::ok && std::isfinite(e[0]) && std::isfinite(e[1]);
    };
    auto plain_miss = [&](double a, double s) {
        simulated_a = a, simulated_s = s;
        std::array<double, N> x;
        for (std::size_t i = 0; i < N; ++i) x[i] = ws.x_start[i] = start_state(a, s, i);
        double at_mid = 0.0;
        const auto watch = [&](std::size_t i, const std::array<double, N>& state, const std::vector<double>&) {
            if (i == mid) at_mid = state[node];
            return !ws.stop_requested();
        };
        status = march_fixed_rk4<N>(ws.model, *ws.inputs, w.start, w.first, x, d_->simulation.max_step,
                                    ws.buffers.u, ws.buffers.u_stages, ws.buffers.rhs_evaluations, watch);
        for (std::size_t i = 0; i < N; ++i) ws.x[i] = x[i];
        e[0] = at_mid - angle[mid];
        e[1] = x[node] - angle[w.first];
        return status == SimulationStatus::ok && std::isfinite(e[0]) && std::isfinite(e[1]);
    };
    auto newton_step = [&](double& a, double& s) {
        const double det = jac[0][0] * jac[1][1] - jac[0][1] * jac[1][0];
        if (!std::isfinite(det) || det == 0.0) return false;
        a -= (jac[1][1] * e[0] - jac[0][1] * e[1]) / det;
        s -= (-jac[1][0] * e[0] + jac[0][0] * e[1]) / det;
        return std::isfinite(a) && std::isfinite(s);
    };
    const double tolerance = 1e-12 + 1e-15 * std::abs(angle[w.first]);
    const double coarse_tolerance = 1e-7;  // how close the coarse Newton's guess gets
    const auto below = [&](double limit) { return std::abs(e[0]) < limit && std::abs(e[1]) < limit; };
    const auto solution_at_last_simulation = [&] {
        start.offset = simulated_a;
        start.speed = simulated_s;
    };
    double a = 0.0, s = ws.x0[n + node];
    start.shot = false;
    ws.x_start = ws.x;

    // 2. and 3., from a full simulation with tangents just run at (a, s).
    const auto finish_from_tangents = [&]() {
        start.shot = below(tolerance);
        if (!start.shot && !newton_step(a, s)) return status;  // no handle on the rigid motion: keep the start so far
        start.shot = true;
        for (int it = 0; it < 8 && !below(tolerance); ++it) {
            if (!plain_miss(a, s)) break;
            if (below(tolerance) || !newton_step(a, s)) break;
            if (it == 7) plain_miss(a, s);
        }
        solution_at_last_simulation();
        return status;  // ws.x: the state at w.first
    };

    // 1'. From a guess at nearby parameters: chord steps with the Jacobian of the miss
    // computed there, on plain simulations, while each cuts the miss at least tenfold (the
    // map differs little between nearby parameters: mostly the rigid motion's a + s·t).
    for (const ShootingGuess& g : ws.shooting_guesses) {
        if (g.start != w.start || g.first != w.first || !std::isfinite(g.offset) || !std::isfinite(g.speed)) continue;
        a = g.offset, s = g.speed;
        jac = g.miss_jacobian;
        double last_miss = std::numeric_limits<double>::infinity(), last_e[2] = {0, 0}, step[2] = {0, 0};
        for (int it = 0; it < 6 && plain_miss(a, s); ++it) {
            const double miss = std::max(std::abs(e[0]), std::abs(e[1]));
            if (it > 0) {  // Broyden's update: the Jacobian takes the secant of the last step
                const double de[2] = {e[0] - last_e[0], e[1] - last_e[1]};
                const double norm2 = step[0] * step[0] + step[1] * step[1];
                for (int row = 0; row < 2 && norm2 > 0; ++row) {
                    const double f = (de[row] - jac[row][0] * step[0] - jac[row][1] * step[1]) / norm2;
                    jac[row][0] += f * step[0], jac[row][1] += f * step[1];
                }
            }
            if (below(tolerance)) {
                start.shot = true;
                start.miss_jacobian = jac;
                solution_at_last_simulation();
                return status;
            }
            if (!(miss < 0.1 * last_miss)) break;
            last_miss = miss, last_e[0] = e[0], last_e[1] = e[1];
            const double a_before = a, s_before = s;
            if (!newton_step(a, s)) break;
            step[0] = a - a_before, step[1] = s - s_before;
        }
        if (ws.stop_requested()) return status;
        a = 0.0, s = ws.x0[n + node];  // too far, or failed there: as without a guess
        status = SimulationStatus::ok;
        break;
    }
    // 1. The guess from the coarse simulation.
    if (d_->simulation.max_step > 0.0) {
        double ca = a, cs = s;
        bool usable = false;
        for (int it = 0; it < 8; ++it) {
            if (!tangent_miss(ca, cs, 0.0)) break;
            if (below(coarse_tolerance)) {
                usable = true;
                break;
            }
            if (!newton_step(ca, cs)) break;
        }
        if (usable) a = ca, s = cs;
        status = SimulationStatus::ok;
    }
    // 2. Newton with the full simulation's tangents.
    if (!tangent_miss(a, s, d_->simulation.max_step)) return status;
    return finish_from_tangents();
}

SimulationStatus WindowStarts::shoot_warmup(const Window& w, ProblemWorkspace& ws, WindowStart& start) const {
    const auto by_differences = [&] { return shoot_warmup_by_differences(w, ws, start); };
    if (d_->simulation.method != IntegrationMethod::rk4 || !(w.start + (w.first - w.start) / 2 > w.start))
        return by_differences();
    const auto newton = [&]<std::size_t N>(std::integral_constant<std::size_t, N>) {
        return shoot_warmup_newton<N>(w, ws, start);
    };
    return dispatch_state_size(ws.model.state_size(), newton, by_differences);
}

SimulationStatus WindowStarts::shoot_warmup_by_differences(const Window& w, ProblemWorkspace& ws,
                                                           WindowStart& start) const {
    // The methodology paper's measured initial state made consistent with the encoder. Every node starts
    // at the measured crank angle turning at the measured speed, untwisted. The fast twist
    // modes forget that within milliseconds, but the slow rigid-body mode (its error decays
    // only with ΣJ/ΣC, seconds) would keep any error of the start, e.g. the twist between
    // a light measured wheel and the heavy flywheel. So its two unknowns, a common angle
    // offset a and a common speed s, are solved for: the encoder's node must meet the
    // measured crank angle at the middle and at the end of the warm-up, after the twist
    // transient has died out (chord Newton on the 2×2 system).
    const std::size_t n = ws.model.node_count();
    const auto node = static_cast<std::size_t>(d_->angle_node);
    const std::size_t mid = w.start + (w.first - w.start) / 2;
    const std::vector<double>& angle = d_->crank_angle;
    ws.x0 = ws.x;
    SimulationStatus status = SimulationStatus::ok;
    auto miss = [&](double a, double s, double e[2]) {
        ws.x = ws.x0;
        for (std::size_t i = 0; i < n; ++i) {
            ws.x[i] += a * speed_ratio(ws.x0, n, node, i);
            ws.x[n + i] = s * speed_ratio(ws.x0, n, node, i);
        }
        ws.x_start = ws.x;
        double at_mid = 0.0;
        const auto watch = [&](std::size_t i, const std::vector<double>& x, const std::vector<double>&) {
            if (i == mid) at_mid = x[node];
            return !ws.stop_requested();
        };
        status = simulate_samples(ws.model, *ws.inputs, w.start, w.first, ws.x, d_->simulation, ws.buffers, watch);
        e[0] = at_mid - angle[mid];
        e[1] = ws.x[node] - angle[w.first];
        return status == SimulationStatus::ok && std::isfinite(e[0]) && std::isfinite(e[1]);
    };
    double a = 0.0, s = ws.x0[n + node], e[2], ea[2], es[2];
    start.shot = false;
    ws.x_start = ws.x;
    if (mid <= w.start) {  // too short to shoot: a plain warm-up from the measured state
        const auto plain = [&](std::size_t, const std::vector<double>&, const std::vector<double>&) {
            return !ws.stop_requested();
        };
        return simulate_samples(ws.model, *ws.inputs, w.start, w.first, ws.x, d_->simulation, ws.buffers, plain);
    }
    if (!miss(a, s, e)) return status;
    // The Jacobian by differences, once: the map is close to linear.
    const double da = 1e-6, ds = 1e-4;
    if (!miss(a + da, s, ea) || !miss(a, s + ds, es)) return status;
    const double j00 = (ea[0] - e[0]) / da, j10 = (ea[1] - e[1]) / da;
    const double j01 = (es[0] - e[0]) / ds, j11 = (es[1] - e[1]) / ds;
    const double det = j00 * j11 - j01 * j10;
    if (!std::isfinite(det) || det == 0.0) {  // no handle on the rigid motion: keep the measured start
        miss(a, s, e);
        return status;
    }
    const double tolerance = 1e-12 + 1e-15 * std::abs(angle[w.first]);
    start.shot = true;
    for (int it = 0; it < 6; ++it) {
        a -= (j11 * e[0] - j01 * e[1]) / det;
        s -= (-j10 * e[0] + j00 * e[1]) / det;
        start.offset = a, start.speed = s;
        if (!miss(a, s, e)) return status;
        if (std::abs(e[0]) < tolerance && std::abs(e[1]) < tolerance) break;
    }
    return status;  // ws.x: the state at w.first
}

WindowStart WindowStarts::start(const Window& w, ProblemWorkspace& ws, std::string* problem) const {
    WindowStart start;
    if (!initial_state(w, ws, problem)) {
        start.status = SimulationStatus::not_finite;
        return start;
    }
    ws.x_start = ws.x;
    if (warms_up(w)) {
        start.status = shoot_warmup(w, ws, start);
        start.mid = w.start + (w.first - w.start) / 2;
        start.node = static_cast<std::size_t>(d_->angle_node);
        if (start.status != SimulationStatus::ok && problem)
            *problem = std::string("warm-up simulation ") + to_string(start.status);
    }
    return start;
}

WindowStart WindowStarts::restore(const SolvedStart& solved, ProblemWorkspace& ws) {
    ws.x_start = solved.x_start;
    ws.x = solved.x;
    ws.u0 = solved.u0;
    return solved.start;
}

}  // namespace tvid

#include "tvid/estimation/window_start.hpp"
#include "tvid/estimation/stable_step.hpp"
#include "tvid/estimation/warmup_newton.hpp"

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

std::size_t WindowStarts::estimation_index(const Window& w) const {
    for (std::size_t k = 0; k < d_->estimation.size(); ++k) {
        const Window& e = d_->estimation[k];
        if (&e == &w || (e.start == w.start && e.first == w.first && e.last == w.last && e.recording == w.recording))
            return k;
    }
    return kNotEstimation;
}

std::pair<std::size_t, std::size_t> WindowStarts::estimated_start_samples(const Window& w) const {
    // The window's warm-up, or the lead-in the loader gave it (experiment/estimated_start.cpp):
    // the residuals of samples (w.start, w.first), none of them scored.
    return {w.start, w.first > w.start ? w.first - 1 : w.start};
}

bool WindowStarts::initial_state(const Window& w, ProblemWorkspace& ws, std::string* problem) const {
    const ProblemDefinition::EstimatedStarts& estimated = d_->estimated;
    if (estimated.on) {
        if (const std::size_t k = estimation_index(w); k != kNotEstimation) {
            if (k >= estimated.seed.size() || estimated.seed[k].size() != ws.x.size()) {
                if (problem) *problem = "the estimated start has no seed";
                return false;
            }
            // The seed (the recipe's state at the parameters' init) plus the window's corrections.
            std::size_t hint = w.start;
            ws.inputs->at(d_->inputs.time()[w.start], hint, ws.u0.data());
            ws.x = estimated.seed[k];
            const std::vector<double>& p = ws.model.parameters();
            for (const NetworkSpec::StartCoordinate& c : estimated.of_window[k])
                ws.x[c.state] += p[static_cast<std::size_t>(c.parameter)];
            ws.model.project_onto_ties(ws.x.data());  // a node an ideal gear ties follows its root
            return true;
        }
        if (!recipe_state(w, ws, problem)) return false;
        if (!estimated.validation) return true;
        const StepPlan plan = stable_step_plan(*d_, w, ws);  // the fit of the start simulates too
        ws.substeps = plan.substeps;
        ws.implicit_steps = plan.implicit;
        return estimate_start(w, ws, problem);
    }
    return recipe_state(w, ws, problem);
}

bool WindowStarts::recipe_state(const Window& w, ProblemWorkspace& ws, std::string* problem) const {
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
                if (d_->network.nodes[i].holds_state) continue;  // a controller's integral: empty
                ws.x[i] = ratio(i) == angle_ratio ? angle : ratio(i) / angle_ratio * angle;
                ws.x[n + i] = ratio(i) * speed;
            }
            return true;
        }
        case InitialStateKind::steady: {
            // The line in steady rotation at the node's (mean) speed under the mean inputs
            // of the averaged samples, which ws.u0 keeps (the start's sensitivity reads them).
            const SteadyStartSpec& s = d_->steady;
            // Cut at the end of the window's recording, as at the end of a single file.
            const std::size_t count = w.recording < d_->recordings.size() ? d_->recordings[w.recording].end
                                                                          : d_->inputs.samples();
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

SimulationStatus WindowStarts::shoot_warmup(const Window& w, ProblemWorkspace& ws, WindowStart& start) const {
    const auto by_differences = [&] { return shoot_warmup_by_differences(w, ws, start); };
    if (!steps_by_rk4(d_->simulation.method) || ws.implicit_steps || !(w.start + (w.first - w.start) / 2 > w.start))
        return by_differences();
    const auto newton = [&]<std::size_t N>(std::integral_constant<std::size_t, N>) {
        return WarmupNewton<N>(*d_, w, ws, start).solve();
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
        status = simulate_samples(ws.model, *ws.inputs, w.start, w.first, ws.x, window_settings(*d_, w, ws), ws.buffers,
                                  watch);
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
        return simulate_samples(ws.model, *ws.inputs, w.start, w.first, ws.x, window_settings(*d_, w, ws), ws.buffers,
                                plain);
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
    // The step of this window's simulations at these parameters (stable_step.hpp).
    const StepPlan plan = stable_step_plan(*d_, w, ws);
    ws.substeps = start.substeps = plan.substeps;
    ws.implicit_steps = start.implicit_steps = plan.implicit;
    if (start.substeps > 1 && subdivided_) subdivided_->fetch_add(1, std::memory_order_relaxed);
    if (start.implicit_steps && implicit_) implicit_->fetch_add(1, std::memory_order_relaxed);
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
    ws.substeps = solved.start.substeps;
    ws.implicit_steps = solved.start.implicit_steps;
    return solved.start;
}

}  // namespace tvid

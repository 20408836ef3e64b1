#include "tvid/estimation/identification_problem.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <type_traits>

#include "tvid/model/equilibrium.hpp"
#include "tvid/sim/fixed_state_rk4.hpp"

namespace tvid {

namespace {
std::vector<double> scaled(const std::vector<double>& v, double scale) {
    std::vector<double> out(v);
    if (scale != 1.0)
        for (double& x : out) x *= scale;
    return out;
}
}  // namespace

IdentificationProblem::IdentificationProblem(const Experiment& experiment) : experiment_(&experiment) {
    const CsvTable& data = experiment.data;
    std::vector<std::vector<double>> input_values, angle_values;
    for (const ChannelBinding& in : experiment.inputs)
        (in.by_angle ? angle_values : input_values).push_back(scaled(data.column(in.column), in.scale));
    inputs_ = InputChannels(data.column(experiment.time_column), std::move(input_values));
    if (!angle_values.empty()) angle_inputs_ = CrankAngleChannels(experiment.crank_angle, std::move(angle_values));
    for (const ChannelBinding& out : experiment.outputs)
        measured_.push_back(scaled(data.column(out.column), out.scale));

    fixed_values_.resize(experiment.parameters.size());
    for (std::size_t i = 0; i < experiment.parameters.size(); ++i) {
        const ParameterSetting& p = experiment.parameters[i];
        fixed_values_[i] = p.init;
        if (p.fixed) continue;
        free_.push_back(i);
        free_names_.push_back(p.name);
        lower_.push_back(p.min);
        upper_.push_back(p.max);
        range_lo_.push_back(p.range ? p.range->first : p.min);
        range_hi_.push_back(p.range ? p.range->second : p.max);
        init_.push_back(p.init);
    }
}

std::unique_ptr<ProblemWorkspace> IdentificationProblem::make_workspace() const {
    auto ws = std::make_unique<ProblemWorkspace>(experiment_->network);
    ws->model.set_crank_angle_inputs(&angle_inputs_);
    ws->tangent_model.set_crank_angle_inputs(&angle_inputs_);
    ws->tangent_params.resize(experiment_->network.parameter_names.size());
    ws->params = fixed_values_;
    ws->x.resize(ws->model.state_size());
    ws->u0.resize(inputs_.count());
    ws->buffers.u.resize(inputs_.count());
    return ws;
}

void IdentificationProblem::full_parameters(const double* free, std::vector<double>& out) const {
    out = fixed_values_;
    for (std::size_t j = 0; j < free_.size(); ++j) out[free_[j]] = free[j];
}

std::vector<double> IdentificationProblem::full_parameters(const std::vector<double>& free) const {
    std::vector<double> out;
    full_parameters(free.data(), out);
    return out;
}

bool IdentificationProblem::initial_state(std::size_t start, ProblemWorkspace& ws, std::string* problem) const {
    const std::size_t n = ws.model.node_count();
    std::size_t hint = start;
    inputs_.at(inputs_.time()[start], hint, ws.u0.data());
    std::fill(ws.x.begin(), ws.x.end(), 0.0);
    switch (experiment_->initial_state) {
        case InitialStateKind::rest: return true;
        case InitialStateKind::measured: {
            // Every node at the measured crank angle (no twist), turning at the measured speed.
            const double speed = measured_[static_cast<std::size_t>(experiment_->initial_speed_output)][start];
            for (std::size_t i = 0; i < n; ++i) {
                ws.x[i] = experiment_->crank_angle[start];
                ws.x[n + i] = speed;
            }
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
SimulationStatus IdentificationProblem::shoot_warmup_newton(const Window& w, ProblemWorkspace& ws, WindowStart& start) const {
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
    const auto node = static_cast<std::size_t>(experiment_->angle_node);
    const std::size_t mid = w.start + (w.first - w.start) / 2;
    const std::vector<double>& angle = experiment_->crank_angle;
    const std::vector<double>& p = ws.model.parameters();
    for (std::size_t i = 0; i < p.size(); ++i) ws.tangent_params[i] = T(p[i]);
    ws.tangent_model.set_parameters(ws.tangent_params.data());
    ws.x0 = ws.x;
    SimulationStatus status = SimulationStatus::ok;
    double e[2];
    MissJacobian jac{};
    double simulated_a = 0.0, simulated_s = 0.0;  // the start of the last simulation: where ws.x comes from
    auto start_state = [&](double a, double s, std::size_t i) { return i < n ? ws.x0[i] + a : s; };
    auto tangent_miss = [&](double a, double s, double max_step) {
        simulated_a = a, simulated_s = s;
        std::array<T, N> x;
        for (std::size_t i = 0; i < N; ++i) {
            x[i] = T(start_state(a, s, i));
            x[i].set_derivative(i < n ? 0 : 1, 1.0);  // ∂θ_i/∂a, ∂ω_i/∂s
            ws.x_start[i] = x[i].value();
        }
        T at_mid;
        const auto watch = [&](std::size_t i, const std::array<T, N>& state, const std::vector<double>&) {
            if (i == mid) at_mid = state[node];
            return !ws.stop_requested();
        };
        status = march_fixed_rk4<N>(ws.tangent_model, inputs_, w.start, w.first, x, max_step, ws.buffers.u,
                                    ws.buffers.u_stages, ws.buffers.rhs_evaluations, watch);
        for (std::size_t i = 0; i < N; ++i) ws.x[i] = x[i].value();
        e[0] = at_mid.value() - angle[mid];
        e[1] = x[node].value() - angle[w.first];
        jac[0][0] = at_mid.derivative(0), jac[0][1] = at_mid.derivative(1);
        jac[1][0] = x[node].derivative(0), jac[1][1] = x[node].derivative(1);
        if (max_step == experiment_->simulation.max_step) start.miss_jacobian = jac;
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
        status = march_fixed_rk4<N>(ws.model, inputs_, w.start, w.first, x, experiment_->simulation.max_step,
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
    double a = 0.0, s = ws.x0[n];
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
                for (int r = 0; r < 2 && norm2 > 0; ++r) {
                    const double f = (de[r] - jac[r][0] * step[0] - jac[r][1] * step[1]) / norm2;
                    jac[r][0] += f * step[0], jac[r][1] += f * step[1];
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
        a = 0.0, s = ws.x0[n];  // too far, or failed there: as without a guess
        status = SimulationStatus::ok;
        break;
    }
    // 1. The guess from the coarse simulation.
    if (experiment_->simulation.max_step > 0.0) {
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
    if (!tangent_miss(a, s, experiment_->simulation.max_step)) return status;
    return finish_from_tangents();
}

SimulationStatus IdentificationProblem::shoot_warmup(const Window& w, ProblemWorkspace& ws, WindowStart& start) const {
    const std::size_t state = ws.model.state_size();
    if (experiment_->simulation.method == IntegrationMethod::rk4 && state <= kMaxFixedState && state % 2 == 0 &&
        w.start + (w.first - w.start) / 2 > w.start) {
        const auto run = [&]<std::size_t N>(std::integral_constant<std::size_t, N>) {
            return shoot_warmup_newton<N>(w, ws, start);
        };
        switch (state) {
            case 2: return run(std::integral_constant<std::size_t, 2>{});
            case 4: return run(std::integral_constant<std::size_t, 4>{});
            case 6: return run(std::integral_constant<std::size_t, 6>{});
            case 8: return run(std::integral_constant<std::size_t, 8>{});
            case 10: return run(std::integral_constant<std::size_t, 10>{});
            case 12: return run(std::integral_constant<std::size_t, 12>{});
            case 14: return run(std::integral_constant<std::size_t, 14>{});
            case 16: return run(std::integral_constant<std::size_t, 16>{});
            default: break;
        }
    }
    // The methodology paper's measured initial state made consistent with the encoder. Every node starts
    // at the measured crank angle turning at the measured speed, untwisted. The fast twist
    // modes forget that within milliseconds, but the slow rigid-body mode (its error decays
    // only with ΣJ/ΣC, seconds) would keep any error of the start, e.g. the twist between
    // a light measured wheel and the heavy flywheel. So its two unknowns, a common angle
    // offset a and a common speed s, are solved for: the encoder's node must meet the
    // measured crank angle at the middle and at the end of the warm-up, after the twist
    // transient has died out (chord Newton on the 2×2 system).
    const std::size_t n = ws.model.node_count();
    const auto node = static_cast<std::size_t>(experiment_->angle_node);
    const std::size_t mid = w.start + (w.first - w.start) / 2;
    const std::vector<double>& angle = experiment_->crank_angle;
    ws.x0 = ws.x;
    SimulationStatus status = SimulationStatus::ok;
    auto miss = [&](double a, double s, double e[2]) {
        ws.x = ws.x0;
        for (std::size_t i = 0; i < n; ++i) {
            ws.x[i] += a;
            ws.x[n + i] = s;
        }
        ws.x_start = ws.x;
        double at_mid = 0.0;
        const auto watch = [&](std::size_t i, const std::vector<double>& x, const std::vector<double>&) {
            if (i == mid) at_mid = x[node];
            return !ws.stop_requested();
        };
        status = simulate_samples(ws.model, inputs_, w.start, w.first, ws.x, experiment_->simulation, ws.buffers, watch);
        e[0] = at_mid - angle[mid];
        e[1] = ws.x[node] - angle[w.first];
        return status == SimulationStatus::ok && std::isfinite(e[0]) && std::isfinite(e[1]);
    };
    double a = 0.0, s = ws.x0[n], e[2], ea[2], es[2];
    start.shot = false;
    ws.x_start = ws.x;
    if (mid <= w.start) {  // too short to shoot: a plain warm-up from the measured state
        const auto plain = [&](std::size_t, const std::vector<double>&, const std::vector<double>&) {
            return !ws.stop_requested();
        };
        return simulate_samples(ws.model, inputs_, w.start, w.first, ws.x, experiment_->simulation, ws.buffers, plain);
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

WindowStart IdentificationProblem::start_window(const Window& w, ProblemWorkspace& ws, std::string* problem) const {
    WindowStart start;
    if (!initial_state(w.start, ws, problem)) {
        start.status = SimulationStatus::not_finite;
        return start;
    }
    ws.x_start = ws.x;
    if (experiment_->initial_state == InitialStateKind::measured && w.start < w.first) {
        start.status = shoot_warmup(w, ws, start);
        start.mid = w.start + (w.first - w.start) / 2;
        start.node = static_cast<std::size_t>(experiment_->angle_node);
        if (start.status != SimulationStatus::ok && problem)
            *problem = std::string("warm-up simulation ") + to_string(start.status);
    }
    return start;
}

template <class Observer>
SimulationStatus IdentificationProblem::simulate_window(const Window& w, ProblemWorkspace& ws, std::string* problem,
                                                        Observer&& on_scored, SolvedStart* solved) const {
    const WindowStart start = start_window(w, ws, problem);
    if (start.status != SimulationStatus::ok) return start.status;
    if (solved) {  // assigned member by member: the vectors keep their storage
        solved->start = start;
        solved->x_start = ws.x_start;
        solved->x = ws.x;
        solved->u0 = ws.u0;
    }
    std::size_t from = w.start;
    if (experiment_->initial_state == InitialStateKind::measured && w.start < w.first) {
        from = w.first;
        // After a warm-up the first sample is a prediction too: score it.
        std::size_t hint = w.first;
        inputs_.at(inputs_.time()[w.first], hint, ws.buffers.u.data());
        if (!on_scored(w.first, ws.x, ws.buffers.u)) return SimulationStatus::stopped_by_observer;
    }
    const auto scored = [&](std::size_t i, const std::vector<double>& x, const std::vector<double>& u) {
        if (ws.stop_requested()) return false;
        return i < w.first ? true : on_scored(i, x, u);  // warm-up: simulated, not scored
    };
    const SimulationStatus status =
        simulate_samples(ws.model, inputs_, from, w.last, ws.x, experiment_->simulation, ws.buffers, scored);
    if (status != SimulationStatus::ok && problem) *problem = std::string("simulation ") + to_string(status);
    return status;
}

double IdentificationProblem::cost(const double* free, ProblemWorkspace& ws) const {
    return cost(free, ws, std::numeric_limits<double>::infinity());
}

std::size_t IdentificationProblem::scored_samples(const Window& w) const {
    // As simulate_window: after a warm-up from a measured state, samples first … last;
    // otherwise the samples after the start from the first scored one on.
    if (experiment_->initial_state == InitialStateKind::measured && w.start < w.first) return w.last - w.first + 1;
    const std::size_t from = std::max(w.start + 1, w.first);
    return w.last >= from ? w.last - from + 1 : 0;
}

double IdentificationProblem::cost(const double* free, ProblemWorkspace& ws, double bound) const {
    for (std::size_t j = 0; j < free_.size(); ++j) {
        if (!std::isfinite(free[j])) return std::numeric_limits<double>::infinity();
        ws.params[free_[j]] = free[j];
    }
    ws.model.set_parameters(ws.params.data());
    const bool l1 = experiment_->estimation_settings.cost == CostKind::l1;
    const std::size_t n_out = experiment_->outputs.size();
    const bool bounded = bound < std::numeric_limits<double>::infinity();
    double total = 0.0;
    for (const Window& w : experiment_->estimation) {
        double window_sum = 0.0;
        std::size_t scored = 0;
        // The window's share as the total will add it up, from the sum so far: it only grows
        // (terms >= 0, rounding is monotonic), so once it reaches the bound the cost will too.
        const auto n_scored = static_cast<double>(scored_samples(w));
        auto share = [&] { return l1 ? window_sum / n_scored : window_sum; };
        bool cut = false;
        auto score = [&](std::size_t i, const std::vector<double>& x, const std::vector<double>& u) {
            for (std::size_t k = 0; k < n_out; ++k) {
                const double e = ws.model.output(experiment_->output_indices[k], x.data(), u.data()) - measured_[k][i];
                window_sum += l1 ? std::abs(e) : e * e;
            }
            ++scored;
            if (bounded && total + share() >= bound) cut = true;
            return !cut;
        };
        const SimulationStatus status = simulate_window(w, ws, nullptr, score);
        if (cut) return total + share();
        if (status != SimulationStatus::ok) return std::numeric_limits<double>::infinity();
        total += l1 ? window_sum / static_cast<double>(scored) : window_sum;  // l1: mean per window
    }
    return std::isfinite(total) ? total : std::numeric_limits<double>::infinity();
}

WindowStart IdentificationProblem::restore_start(const SolvedStart& solved, ProblemWorkspace& ws) {
    ws.x_start = solved.x_start;
    ws.x = solved.x;
    ws.u0 = solved.u0;
    return solved.start;
}

bool IdentificationProblem::residuals(const double* free, ProblemWorkspace& ws, std::vector<double>& out,
                                      std::vector<SolvedStart>* starts) const {
    out.clear();
    if (starts) starts->resize(experiment_->estimation.size());
    for (std::size_t j = 0; j < free_.size(); ++j) {
        if (!std::isfinite(free[j])) return false;
        ws.params[free_[j]] = free[j];
    }
    ws.model.set_parameters(ws.params.data());
    const std::size_t n_out = experiment_->outputs.size();
    for (std::size_t wi = 0; wi < experiment_->estimation.size(); ++wi) {
        auto record = [&](std::size_t i, const std::vector<double>& x, const std::vector<double>& u) {
            for (std::size_t k = 0; k < n_out; ++k)
                out.push_back(ws.model.output(experiment_->output_indices[k], x.data(), u.data()) - measured_[k][i]);
            return true;
        };
        if (simulate_window(experiment_->estimation[wi], ws, nullptr, record, starts ? &(*starts)[wi] : nullptr) !=
            SimulationStatus::ok)
            return false;
    }
    return true;
}

WindowTrace IdentificationProblem::trace(const std::vector<double>& params, const Window& window,
                                         ProblemWorkspace& ws) const {
    WindowTrace tr;
    tr.window = &window;
    const std::size_t n_out = experiment_->outputs.size();
    tr.measured.assign(n_out, {});
    tr.simulated.assign(n_out, {});
    ws.params = params;
    ws.model.set_parameters(ws.params.data());
    auto record = [&](std::size_t i, const std::vector<double>& x, const std::vector<double>& u) {
        tr.samples.push_back(i);
        tr.time.push_back(inputs_.time()[i]);
        for (std::size_t k = 0; k < n_out; ++k) {
            tr.measured[k].push_back(measured_[k][i]);
            tr.simulated[k].push_back(ws.model.output(experiment_->output_indices[k], x.data(), u.data()));
        }
        return true;
    };
    tr.status = simulate_window(window, ws, &tr.problem, record);
    return tr;
}

}  // namespace tvid

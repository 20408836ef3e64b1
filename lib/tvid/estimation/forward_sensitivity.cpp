#include "tvid/estimation/forward_sensitivity.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <type_traits>

#include "tvid/channels/channel_delay.hpp"
#include "tvid/estimation/stable_step.hpp"
#include "tvid/model/steady_motion.hpp"
#include "tvid/sim/fixed_state_rk4.hpp"
#include "tvid/sim/sensitivity_system.hpp"
#include "tvid/sim/state_size_dispatch.hpp"

namespace tvid {

namespace {

// How the residual y − y*(t + d) of an output read with delay d moves with d: the model
// does not see the delay, the recording moves under it, so −y*'(t + d) (the slope of the
// interpolation, channel_delay.hpp). Every Jacobian and sensitivity column of an output's
// delay is this.
double output_delay_derivative(const SampledSignal& recorded, double t, double delay, std::size_t& hint) {
    return -delayed_slope(recorded, t + delay, hint);
}

// The two Jacobians of the implicit-function theorem for a start that solves F(v, p) = 0
// (the equilibrium's static torques, the steady start's accelerations): with F(v̄(p), p) = 0,
// ∂F/∂v · dv̄/dp = −∂F/∂p. `v` holds the solution as constant dual numbers; its first
// `unknowns` entries are the unknowns v, seeded in blocks of the dual capacity with the
// parameters held; `residual(v)` points at F's `rows` values. ∂F/∂p is taken first, with
// ws.model's parameters as set (the block's `cols` columns seeded), and they are set so again.
template <class Residual>
void implicit_jacobians(std::vector<Dual>& v, std::size_t unknowns, std::size_t rows, std::size_t cols,
                        SensitivityWorkspace& ws, Eigen::MatrixXd& dFdp, Eigen::MatrixXd& dFdv, Residual&& residual) {
    const auto at = [](std::size_t i) { return static_cast<Eigen::Index>(i); };
    dFdp.resize(at(rows), at(cols));
    dFdv.resize(at(rows), at(unknowns));
    const Dual* f = residual(v);
    for (std::size_t i = 0; i < rows; ++i)
        for (std::size_t j = 0; j < cols; ++j) dFdp(at(i), at(j)) = f[i].derivative(static_cast<int>(j));
    std::vector<Dual> constant(ws.params.size());
    for (std::size_t i = 0; i < constant.size(); ++i) constant[i] = Dual(ws.plain->params[i]);
    ws.model.set_parameters(constant.data());
    const auto capacity = static_cast<std::size_t>(kDualCapacity);
    for (std::size_t c0 = 0; c0 < unknowns; c0 += capacity) {
        const std::size_t c1 = std::min(unknowns, c0 + capacity);
        for (std::size_t i = 0; i < unknowns; ++i)
            v[i] = i >= c0 && i < c1 ? Dual::variable(v[i].value(), static_cast<int>(i - c0), static_cast<int>(c1 - c0))
                                     : Dual(v[i].value());
        f = residual(v);
        for (std::size_t i = 0; i < rows; ++i)
            for (std::size_t k = c0; k < c1; ++k) dFdv(at(i), at(k)) = f[i].derivative(static_cast<int>(k - c0));
    }
    ws.model.set_parameters(ws.params.data());
}

// z = [x, S] (S with d directions) from sample `first` to `to` with the window's settings:
// odeint's steppers on the augmented system, or sdirk3's implicit steps carrying S
// (sim/sdirk3.hpp), which solve with the plain model and its Jacobian.
template <class Observer>
SimulationStatus march_sensitivities(const SimulationSettings& settings, SensitivitySystem& system, std::size_t first,
                                     std::size_t to, std::size_t d, SensitivityWorkspace& ws, Observer&& observer) {
    const std::size_t state = ws.model.state_size();
    if (settings.method != IntegrationMethod::sdirk3)
        return march_samples(system, *ws.plain->inputs, first, to, ws.z, state, settings, ws.buffers, observer);
    Sdirk3& stepper = ws.buffers.sdirk3;
    stepper.bind(ws.plain->model, *ws.plain->inputs);
    stepper.bind_sensitivities(ws.model, static_cast<int>(d), ws.x, ws.dxdt);
    struct Memory {  // the plain model and its Jacobian at x, the dual model at (x, S)
        Sdirk3& stepper;
        SensitivitySystem& system;
        const std::vector<double>& z;
        void restart(const std::vector<double>& u) {
            stepper.restart_sampling(z.data(), u.data());
            system.restart_sampling(z, u);
        }
        void sample(double t, const std::vector<double>& u) {
            stepper.sample(t, z.data(), u.data());
            system.sample(t, z, u);
        }
    };
    const auto look = [&](std::size_t i) {
        return observer(i, ws.z, ws.buffers.u) ? SimulationStatus::ok : SimulationStatus::stopped_by_observer;
    };
    return march_sdirk3(stepper, *ws.plain->inputs, first, to, ws.z.data(), state, ws.z.data() + state, state * d,
                        settings.max_step, ws.buffers.u, Memory{stepper, system, ws.z}, look);
}

}  // namespace

SensitivityWorkspace::SensitivityWorkspace(const IdentificationProblem& problem)
    : plain(problem.make_workspace()), model(problem.definition().network), packed8(problem), packed16(problem) {
    model.set_crank_angle_inputs(&problem.crank_angle_inputs());
    params.resize(problem.definition().network.parameter_names.size());
    x.resize(model.state_size());
    dxdt.resize(model.state_size());
    y.resize(problem.definition().measured.size());
    buffers.u.resize(problem.inputs().count());
}

std::unique_ptr<SensitivityWorkspace> ForwardSensitivity::make_workspace() const {
    return std::make_unique<SensitivityWorkspace>(*problem_);
}

void ForwardSensitivity::set_parameters(const double* free, std::size_t j0, std::size_t j1, int d,
                                        SensitivityWorkspace& ws) const {
    const std::vector<std::size_t>& index = problem_->free_indices();
    problem_->full_parameters(free, ws.plain->params);
    ws.plain->model.set_parameters(ws.plain->params.data());
    problem_->apply_channel_delays(*ws.plain);
    for (std::size_t i = 0; i < ws.params.size(); ++i) ws.params[i] = Dual(ws.plain->params[i]);
    for (std::size_t j = j0; j < j1; ++j)
        ws.params[index[j]] = Dual::variable(free[j], static_cast<int>(j - j0), d);
    ws.model.set_parameters(ws.params.data());
}

bool ForwardSensitivity::equilibrium_sensitivity(std::size_t j0, std::size_t j1, SensitivityWorkspace& ws,
                                                 Eigen::MatrixXd& dtheta) const {
    // F(θ̄(p), p) = 0, F the static torques.
    const std::size_t n = ws.model.node_count();
    const double* u = ws.plain->u0.data();
    std::vector<Dual> theta(n), torque(n);
    for (std::size_t i = 0; i < n; ++i) theta[i] = Dual(ws.plain->x_start[i]);
    Eigen::MatrixXd dFdp, dFdtheta;
    implicit_jacobians(theta, n, n, j1 - j0, ws, dFdp, dFdtheta, [&](const std::vector<Dual>& at) {
        ws.model.static_torques(at.data(), u, torque.data());
        return torque.data();
    });
    const Eigen::FullPivLU<Eigen::MatrixXd> lu(dFdtheta);
    if (!lu.isInvertible()) return false;
    dtheta = -lu.solve(dFdp);
    return dtheta.allFinite();
}

bool ForwardSensitivity::steady_sensitivity(std::size_t j0, std::size_t j1, SensitivityWorkspace& ws,
                                            Eigen::MatrixXd& dtheta) const {
    // g(z, p) = θ'' − r·α = 0 at the solved start (steady_motion.hpp), z the twists of every
    // node but the reference and α in the reference's slot: the angles are the unknowns,
    // the speeds the given ones.
    const ProblemDefinition& def = problem_->definition();
    const std::size_t n = ws.model.node_count();
    const auto ref = static_cast<std::size_t>(def.steady.node);
    const RigidMotion rigid = rigid_motion(def.network, ws.plain->params, def.steady.node);
    const double* u = ws.plain->u0.data();  // the mean inputs the start balanced
    std::vector<Dual> x(2 * n), dxdt(2 * n);
    for (std::size_t i = 0; i < 2 * n; ++i) x[i] = Dual(ws.plain->x_start[i]);
    Eigen::MatrixXd dgdp, dgdz;
    implicit_jacobians(x, n, n, j1 - j0, ws, dgdp, dgdz, [&](const std::vector<Dual>& at) {
        ws.model.derivative(at.data(), u, dxdt.data());
        for (std::size_t i = 0; i < n; ++i)  // a node an ideal gear ties: its row is the tie (steady_motion.cpp)
            if (ws.model.tied_to_other(i)) dxdt[n + i] = ws.model.tie_constraint(i, at.data());
        return dxdt.data() + n;  // the accelerations
    });
    const auto at = [](std::size_t i) { return static_cast<Eigen::Index>(i); };
    for (std::size_t i = 0; i < n; ++i)  // ∂g_i/∂α
        dgdz(at(i), at(ref)) = ws.model.tied_to_other(i) ? 0.0 : -rigid.ratio[i];
    const Eigen::FullPivLU<Eigen::MatrixXd> lu(dgdz);
    if (!lu.isInvertible()) return false;
    dtheta = -lu.solve(dgdp);
    dtheta.row(at(ref)).setZero();  // the reference's angle is given
    return dtheta.allFinite();
}

bool ForwardSensitivity::start_sensitivity(const Window& w, std::size_t j0, std::size_t j1, SensitivityWorkspace& ws,
                                           Eigen::MatrixXd& dtheta, std::string* problem) const {
    dtheta.resize(0, 0);
    const ProblemDefinition& def = problem_->definition();
    if (def.estimated.on) {
        if (const std::size_t k = problem_->estimation_index(w); k != WindowStarts::kNotEstimation) {
            dtheta.setZero(static_cast<Eigen::Index>(ws.model.state_size()), static_cast<Eigen::Index>(j1 - j0));
            for (const NetworkSpec::StartCoordinate& c : def.estimated.of_window[k])
                if (const long j = problem_->free_column(c.parameter); j >= static_cast<long>(j0) && j < static_cast<long>(j1))
                    dtheta(static_cast<Eigen::Index>(c.state), static_cast<Eigen::Index>(j - static_cast<long>(j0))) = 1.0;
            // A node an ideal gear ties follows its root: x_i = f_i·x_root (window_start.cpp).
            const std::size_t n = ws.model.node_count();
            for (std::size_t i = 0; i < n && ws.model.ties_nodes(); ++i) {
                if (!ws.model.tied_to_other(i)) continue;
                const std::size_t r = ws.model.tie_root(i);
                const Dual& f = ws.model.tie_factor(i);
                for (const std::size_t s : {std::size_t{0}, n})
                    for (Eigen::Index j = 0; j < dtheta.cols(); ++j)
                        dtheta(static_cast<Eigen::Index>(s + i), j) =
                            f.value() * dtheta(static_cast<Eigen::Index>(s + r), j) +
                            ws.plain->x_start[s + r] * f.derivative(static_cast<int>(j));
            }
            return true;
        }
    }
    switch (problem_->definition().initial_state) {
        case InitialStateKind::equilibrium:
            if (equilibrium_sensitivity(j0, j1, ws, dtheta)) return true;
            if (problem) *problem = "the equilibrium start has no sensitivity (singular static stiffness)";
            return false;
        case InitialStateKind::steady:
            if (steady_sensitivity(j0, j1, ws, dtheta)) return true;
            if (problem) *problem = "the steady start has no sensitivity (singular stiffness in steady motion)";
            return false;
        case InitialStateKind::rest:
        case InitialStateKind::measured: return true;
    }
    return true;
}

WindowStart ForwardSensitivity::window_start(const Window& w, SensitivityWorkspace& ws, std::string* problem,
                                             const SolvedStart* solved) const {
    return solved ? IdentificationProblem::restore_start(*solved, *ws.plain) : problem_->start_window(w, *ws.plain, problem);
}

SimulationStatus ForwardSensitivity::simulate_augmented(const double* free, const Window& w, std::size_t j0,
                                                        std::size_t j1, SensitivityWorkspace& ws, std::string* problem,
                                                        FunctionRef<bool(std::size_t, const Dual*)> on_scored,
                                                        const SolvedStart* solved) const {
    const ProblemDefinition& def = problem_->definition();
    const std::size_t cols = j1 - j0, state = ws.model.state_size(), n = ws.model.node_count();
    set_parameters(free, j0, j1, static_cast<int>(cols), ws);
    const WindowStart start = window_start(w, ws, problem, solved);
    if (start.status != SimulationStatus::ok) return start.status;

    // z = [x, S] at w.start; with a solved warm-up two more directions: the offset a, the speed s.
    std::size_t d = cols + (start.shot ? 2 : 0);
    if (d != cols) set_parameters(free, j0, j1, static_cast<int>(d), ws);
    ws.z.assign(state * (1 + d), 0.0);
    std::copy(ws.plain->x_start.begin(), ws.plain->x_start.end(), ws.z.begin());
    Eigen::MatrixXd dtheta;
    if (!start_sensitivity(w, j0, j1, ws, dtheta, problem)) return SimulationStatus::not_finite;
    if (dtheta.size() > 0) {  // the angles' rows, or every state's for an estimated start
        for (std::size_t i = 0; i < static_cast<std::size_t>(dtheta.rows()); ++i)
            for (std::size_t j = 0; j < cols; ++j)
                ws.z[state + i * d + j] = dtheta(static_cast<Eigen::Index>(i), static_cast<Eigen::Index>(j));
    }
    if (start.shot)
        for (std::size_t i = 0; i < n; ++i) {
            const double r = speed_ratio(ws.plain->x_start, n, start.node, i);  // through the gear ratios
            ws.z[state + i * d + cols] = r;             // ∂θ_i/∂a
            ws.z[state + (n + i) * d + cols + 1] = r;  // ∂ω_i/∂s
        }

    const auto outputs = [&](std::size_t i, const std::vector<double>& z, const std::vector<double>& u) {
        SensitivitySystem::unpack(z, state, d, ws.x);
        for (std::size_t k = 0; k < ws.y.size(); ++k)
            ws.y[k] = ws.model.output(def.output_indices[k], ws.x.data(), u.data());
        return on_scored(i, ws.y.data());
    };
    const auto march_augmented = [&](SensitivitySystem& system, std::size_t first, std::size_t to, auto&& observer) {
        return march_sensitivities(window_settings(def, w, *ws.plain), system, first, to, d, ws, observer);
    };
    std::size_t from = w.start;
    if (problem_->warms_up(w)) {
        // The warm-up, watching the encoder node's sensitivity row at the shooting's samples.
        SensitivitySystem warm(ws.model, *ws.plain->inputs, ws.buffers.u, ws.x, ws.dxdt, static_cast<int>(d));
        const std::size_t node = start.node;
        const auto watch = [&](std::size_t i, const std::vector<double>& z, const std::vector<double>&) {
            if (i == start.mid) ws.row_mid.assign(z.begin() + static_cast<std::ptrdiff_t>(state + node * d),
                                                  z.begin() + static_cast<std::ptrdiff_t>(state + node * d + d));
            return !ws.plain->stop_requested();
        };
        const SimulationStatus status = march_augmented(warm, w.start, w.first, watch);
        if (status != SimulationStatus::ok) {
            if (problem) *problem = std::string("warm-up simulation ") + to_string(status);
            return status;
        }
        if (start.shot) {
            // G = (θ_node(mid), θ_node(first)) − measured: d(a, s)/dp = −(∂G/∂(a, s))⁻¹ ∂G/∂p.
            ws.row_first.assign(ws.z.begin() + static_cast<std::ptrdiff_t>(state + node * d),
                                ws.z.begin() + static_cast<std::ptrdiff_t>(state + node * d + d));
            const ShootingSensitivity shooting(ws.row_mid[cols], ws.row_mid[cols + 1], ws.row_first[cols],
                                               ws.row_first[cols + 1]);
            if (!shooting.regular()) {
                if (problem) *problem = ShootingSensitivity::kSingular;
                return SimulationStatus::not_finite;
            }
            // Repack z to the block's columns with the total derivative S_p + S_(a,s)·d(a,s)/dp.
            std::vector<double> packed(state * (1 + cols));
            std::copy(ws.z.begin(), ws.z.begin() + static_cast<std::ptrdiff_t>(state), packed.begin());
            for (std::size_t j = 0; j < cols; ++j) {
                const double da = shooting.offset_slope(ws.row_mid[j], ws.row_first[j]);
                const double ds = shooting.speed_slope(ws.row_mid[j], ws.row_first[j]);
                for (std::size_t i = 0; i < state; ++i) {
                    const double* row = ws.z.data() + state + i * d;
                    packed[state + i * cols + j] = row[j] + row[cols] * da + row[cols + 1] * ds;
                }
            }
            ws.z.swap(packed);
            d = cols;
            set_parameters(free, j0, j1, static_cast<int>(d), ws);
        }
        // After a warm-up the first sample is a prediction too: score it.
        std::size_t hint = w.first;
        ws.plain->inputs->at(problem_->inputs().time()[w.first], hint, ws.buffers.u.data());
        if (!outputs(w.first, ws.z, ws.buffers.u)) return SimulationStatus::stopped_by_observer;
        from = w.first;
    }
    SensitivitySystem system(ws.model, *ws.plain->inputs, ws.buffers.u, ws.x, ws.dxdt, static_cast<int>(d));
    const auto scored = [&](std::size_t i, const std::vector<double>& z, const std::vector<double>& u) {
        if (ws.plain->stop_requested()) return false;
        return i < w.first ? true : outputs(i, z, u);
    };
    const SimulationStatus status = march_augmented(system, from, w.last, scored);
    if (status != SimulationStatus::ok && problem) *problem = std::string("simulation ") + to_string(status);
    return status;
}

template <class Observer>
SimulationStatus ForwardSensitivity::simulate(const double* free, const Window& w, std::size_t j0, std::size_t j1,
                                              SensitivityWorkspace& ws, std::string* problem, Observer&& on_scored,
                                              const SolvedStart* solved) const {
    // Fixed-step RK4 over a small state with few enough directions (the block's columns
    // and the shooting's two): the state itself carries its sensitivities as PackedDual.
    const ProblemDefinition& def = problem_->definition();
    const std::size_t state = ws.model.state_size(), directions = j1 - j0 + 2;
    const auto augmented = [&] { return simulate_augmented(free, w, j0, j1, ws, problem, on_scored, solved); };
    if (!packed_ || !steps_by_rk4(def.simulation.method) || def.measured.size() > 8 || directions > 16)
        return augmented();
    const auto packed = [&]<std::size_t N>(std::integral_constant<std::size_t, N>) {
        return directions <= 8 ? simulate_packed<N, 8>(free, w, j0, j1, ws, problem, on_scored, solved)
                               : simulate_packed<N, 16>(free, w, j0, j1, ws, problem, on_scored, solved);
    };
    return dispatch_state_size(state, packed, augmented);
}

bool ForwardSensitivity::jacobian_columns(const double* free, std::size_t j0, std::size_t j1,
                                          SensitivityWorkspace& ws, Eigen::MatrixXd& J,
                                          const std::vector<SolvedStart>* starts, Eigen::MatrixXd* start_slopes) const {
    const std::size_t m = problem_->dimension();
    for (std::size_t j = 0; j < m; ++j)
        if (!std::isfinite(free[j])) return false;
    const ProblemDefinition& def = problem_->definition();
    const std::vector<double>& time = problem_->inputs().time();
    Eigen::Index row = 0;
    if (starts && starts->size() != def.estimation.size()) starts = nullptr;
    // The block's columns that are an output's delay: the model does not see them, the
    // measurement moves (channel_delay.hpp).
    struct OutputDelayColumn {
        std::size_t column, output;
        const ProblemDefinition::DelayedChannel* channel;
        SampledSignal recorded;  ///< the current window's recording
        double delay;
        std::size_t hint;
    };
    std::vector<OutputDelayColumn> delay_columns;
    for (const ProblemDefinition::DelayedChannel& c : def.delayed_outputs)
        if (const long j = problem_->free_column(c.parameter); j >= static_cast<long>(j0) && j < static_cast<long>(j1))
            delay_columns.push_back({static_cast<std::size_t>(j), c.channel, &c, c.signal(time), free[j], 0});
    for (std::size_t wi = 0; wi < def.estimation.size(); ++wi) {
        const Window& w = def.estimation[wi];
        for (OutputDelayColumn& c : delay_columns) c.recorded = c.channel->signal(time, def.recordings[w.recording]);
        const auto record = [&](std::size_t i, const auto* outputs) {
            for (std::size_t k = 0; k < def.measured.size(); ++k) {
                const auto& y = outputs[k];
                if (row >= J.rows()) return false;
                for (std::size_t j = j0; j < j1; ++j)
                    J(row, static_cast<Eigen::Index>(j)) = def.output_scale[k] * y.derivative(static_cast<int>(j - j0));
                for (OutputDelayColumn& c : delay_columns)
                    if (c.output == k)
                        J(row, static_cast<Eigen::Index>(c.column)) +=
                            def.output_scale[k] * output_delay_derivative(c.recorded, time[i], c.delay, c.hint);
                ++row;
            }
            return true;
        };
        ws.start_slopes.clear();
        const Eigen::Index window_row = row;
        if (simulate(free, w, j0, j1, ws, nullptr, record, starts ? &(*starts)[wi] : nullptr) != SimulationStatus::ok)
            return false;
        // The outputs' detrend and high-pass, as the residuals get them (a column of J is
        // contiguous: one column's block).
        for (std::size_t j = j0; j < j1; ++j)
            problem_->filter_window_residuals(w, &J(window_row, static_cast<Eigen::Index>(j)), 1, 0);
        if (start_slopes) {
            const bool known = ws.start_slopes.size() == 2 * (j1 - j0);
            for (std::size_t j = j0; j < j1; ++j)
                for (std::size_t c = 0; c < 2; ++c)
                    (*start_slopes)(static_cast<Eigen::Index>(2 * wi + c), static_cast<Eigen::Index>(j)) =
                        known ? ws.start_slopes[2 * (j - j0) + c] : 0.0;
        }
    }
    return row == J.rows() && J.middleCols(static_cast<Eigen::Index>(j0), static_cast<Eigen::Index>(j1 - j0)).allFinite();
}

WindowSensitivity ForwardSensitivity::window_sensitivity(const double* free, const Window& w,
                                                         SensitivityWorkspace& ws) const {
    WindowSensitivity out;
    out.window = &w;
    const std::size_t m = problem_->dimension(), n_out = problem_->definition().measured.size();
    out.output.assign(n_out, {});
    out.dydp.assign(n_out, std::vector<std::vector<double>>(m));
    for (std::size_t j0 = 0; j0 < std::max<std::size_t>(m, 1); j0 += kMaxBlock) {
        const std::size_t j1 = std::min(m, j0 + kMaxBlock);
        const bool first_block = j0 == 0;
        const auto record = [&](std::size_t i, const auto* y) {
            if (first_block) out.time.push_back(problem_->inputs().time()[i]);
            for (std::size_t k = 0; k < n_out; ++k) {
                if (first_block) out.output[k].push_back(y[k].value());
                for (std::size_t j = j0; j < j1; ++j)
                    out.dydp[k][j].push_back(y[k].derivative(static_cast<int>(j - j0)));
            }
            return true;
        };
        out.status = simulate(free, w, j0, j1, ws, &out.problem, record);
        if (out.status != SimulationStatus::ok) return out;
    }
    delay_sensitivities(free, w, ws, out);
    return out;
}

void ForwardSensitivity::delay_sensitivities(const double* free, const Window& w, SensitivityWorkspace& ws,
                                             WindowSensitivity& out) const {
    const ProblemDefinition& def = problem_->definition();
    const std::vector<double>& time = problem_->inputs().time();
    // An output's delay moves the recording: the residual y − y*(t + d) changes by −y*'(t + d).
    for (const ProblemDefinition::DelayedChannel& c : def.delayed_outputs) {
        const long j = problem_->free_column(c.parameter);
        if (j < 0) continue;
        std::vector<double>& d = out.dydp[c.channel][static_cast<std::size_t>(j)];
        std::size_t hint = 0;
        for (std::size_t s = 0; s < out.time.size(); ++s)
            d[s] += output_delay_derivative(c.signal(time, def.recordings[w.recording]), out.time[s], free[j], hint);
    }
    // An input's delay moves what drives the model, which carries no derivative of its
    // inputs: central differences of the outputs.
    std::vector<double> point(free, free + problem_->dimension());
    for (const std::size_t j : problem_->input_delay_columns()) {
        const auto [up, down] = problem_->difference_points(j, free[j]);
        point[j] = up;
        const WindowTrace plus = problem_->trace(problem_->full_parameters(point), w, *ws.plain);
        point[j] = down;
        const WindowTrace minus = problem_->trace(problem_->full_parameters(point), w, *ws.plain);
        point[j] = free[j];
        if (plus.status != SimulationStatus::ok || minus.status != SimulationStatus::ok ||
            plus.time.size() != out.time.size() || minus.time.size() != out.time.size()) {
            out.status = plus.status != SimulationStatus::ok ? plus.status : minus.status;
            out.problem = "the difference of input delay " + problem_->free_names()[j] +
                          " did not simulate";
            return;
        }
        for (std::size_t k = 0; k < out.output.size(); ++k)
            for (std::size_t s = 0; s < out.time.size(); ++s)
                out.dydp[k][j][s] = (plus.simulated[k][s] - minus.simulated[k][s]) / (up - down);
    }
}

}  // namespace tvid

#include "tvid/analysis/linear_network.hpp"

#include <algorithm>
#include <cmath>
#include <utility>

#include "tvid/model/dual.hpp"
#include "tvid/model/network_model.hpp"
#include "tvid/model/state_jacobian.hpp"

namespace tvid {

namespace {

// The spec the linearisation evaluates: each kind says how its elements enter
// (elements/NAME.hpp's linearise: a note, and in revolution_mean mode the angle-dependent
// elements replaced by their means over a revolution, with the inertia they add to their
// nodes), and which nodes' speeds are prescribed.
NetworkSpec linearisation_spec(const NetworkSpec& spec, const std::vector<double>& p, AngleDependence mode,
                               const std::vector<double>& x, std::vector<ElementLinearisation>& notes,
                               std::vector<char>& prescribed) {
    NetworkSpec lin = spec;
    const std::size_t n = spec.nodes.size();
    std::vector<std::string> node_names;
    for (const NodeSpec& s : spec.nodes) node_names.push_back(s.name);
    std::vector<double> added_inertia(n, 0.0);
    prescribed.assign(n, 0);
    const LinearisationPoint at{p, x, mode, node_names, added_inertia, prescribed};
    for_each_element_kind([&](auto kind) {
        using Kind = decltype(kind);
        const auto& elements = ElementRow<Kind>::list(spec);
        auto& replaced = ElementRow<Kind>::list(lin);
        for (std::size_t i = 0; i < elements.size(); ++i) {
            LinearNote note = Kind::linearise(elements[i], replaced[i], at);
            notes.push_back({elements[i].name, Kind::type_name, std::move(note.method), std::move(note.note)});
        }
    });
    for (std::size_t i = 0; i < n; ++i) {
        if (added_inertia[i] == 0.0) continue;
        const NodeSpec& s = spec.nodes[i];
        const double v = at.value(s.inertia);
        lin.nodes[i].inertia = Field::value((s.inverse ? 1.0 / v : v) + added_inertia[i]);
        lin.nodes[i].inverse = false;
    }
    return lin;
}

// The step of a central difference in input value v.
double input_step(double v) { return 1e-6 * std::max(1.0, std::abs(v)); }

}  // namespace

const char* angle_dependence_name(AngleDependence a) {
    return a == AngleDependence::revolution_mean ? "revolution_mean" : "operating_point";
}

std::size_t LinearNetwork::angle_state(std::size_t node) const {
    if (node < angle_root.size()) node = angle_root[node];
    for (std::size_t k = 0; k < states.size(); ++k)
        if (states[k] == node) return k;
    return states.size();
}

namespace {

/// A kept column's perturbation moves its node and every node tied to it: ∂/∂q = Σ f_m ∂/∂x_m.
/// The weight of full state `full_state` in kept column `kept` (n nodes).
double tied_column_weight(const NetworkModel<double>& model, std::size_t n, std::size_t kept, std::size_t full_state) {
    const std::size_t node = full_state % n, own = kept % n;
    if (full_state / n != kept / n || model.tie_root(node) != own) return 0.0;
    return model.tie_factor(node);
}

/// The kept states (a node an ideal gear ties keeps none of its own: its group's root's
/// coordinate moves it, θ_i = factor_i·θ_root, so the linear system is the reduced line's),
/// and the names of the states, inputs (with the speed channels' slopes) and outputs.
void name_states_and_channels(const NetworkSpec& spec, const NetworkModel<double>& model, std::size_t input_count,
                              LinearNetwork& sys) {
    const std::size_t n = spec.nodes.size();
    for (const NodeSpec& s : spec.nodes) sys.node_names.push_back(s.name);
    for (std::size_t i = 0; i < n; ++i) {
        sys.angle_factor.push_back(model.tie_factor(i));
        if (model.tied_to_other(i)) continue;
        sys.states.push_back(i);
        sys.state_names.push_back("theta:" + spec.nodes[i].name);
    }
    for (std::size_t i = 0; i < n; ++i) {
        if (sys.prescribed[i]) continue;  // its speed is the input's: the state is read by no equation
        if (model.tied_to_other(i)) continue;
        sys.states.push_back(n + i);
        sys.state_names.push_back("omega:" + spec.nodes[i].name);
    }
    sys.angle_root.resize(n);
    for (std::size_t i = 0; i < n; ++i) sys.angle_root[i] = model.tie_root(i);
    sys.input_names = spec.input_names;
    sys.rate_of.assign(input_count, -1);
    for (std::size_t j = 0; j < spec.input_rates.size(); ++j) {
        const auto of = static_cast<std::size_t>(spec.input_rates[j]);
        sys.rate_of[of] = static_cast<int>(spec.input_names.size() + j);
        sys.input_names.push_back("d(" + spec.input_names[of] + ")/dt");
    }
    sys.input_names.resize(input_count);
    for (const OutputSpec& o : spec.outputs) sys.output_names.push_back(o.name);
}

/// A = ∂f/∂x at the operating point, the kept rows and columns.
void state_matrix(NetworkModel<double>& model, std::size_t n, LinearNetwork& sys) {
    const std::size_t full = 2 * n;
    StateJacobian jacobian;
    jacobian.bind(model);
    std::vector<double> a_full(full * full), f0(full);
    jacobian.evaluate(sys.x.data(), sys.u.data(), a_full.data(), f0.data());
    const auto ns = static_cast<Eigen::Index>(sys.states.size());
    sys.A.resize(ns, ns);
    for (Eigen::Index r = 0; r < ns; ++r)
        for (Eigen::Index c = 0; c < ns; ++c) {
            const std::size_t row = sys.states[static_cast<std::size_t>(r)], col = sys.states[static_cast<std::size_t>(c)];
            if (!model.ties_nodes()) {
                sys.A(r, c) = a_full[row * full + col];
                continue;
            }
            double sum = 0.0;
            for (std::size_t m = 0; m < full; ++m)
                if (const double w = tied_column_weight(model, n, col, m); w != 0.0) sum += w * a_full[row * full + m];
            sys.A(r, c) = sum;
        }
}

/// B = ∂f/∂u and D = ∂y/∂u by central differences (the inputs enter linearly).
void input_matrices(NetworkModel<double>& model, std::size_t n, std::size_t output_count, LinearNetwork& sys) {
    const std::size_t full = 2 * n;
    const std::vector<double>& x = sys.x;
    const std::vector<double>& u = sys.u;
    const auto ns = static_cast<Eigen::Index>(sys.states.size());
    const auto ni = static_cast<Eigen::Index>(u.size());
    const auto no = static_cast<Eigen::Index>(output_count);
    sys.B = Eigen::MatrixXd::Zero(ns, ni);
    sys.D = Eigen::MatrixXd::Zero(no, ni);
    std::vector<double> up = u, fp(full), fm(full);
    for (Eigen::Index j = 0; j < ni; ++j) {
        const auto jj = static_cast<std::size_t>(j);
        const double h = input_step(u[jj]);
        up[jj] = u[jj] + h;
        model.derivative(x.data(), up.data(), fp.data());
        std::vector<double> yp(static_cast<std::size_t>(no)), ym(yp.size());
        for (Eigen::Index k = 0; k < no; ++k) yp[static_cast<std::size_t>(k)] = model.output(static_cast<std::size_t>(k), x.data(), up.data());
        up[jj] = u[jj] - h;
        model.derivative(x.data(), up.data(), fm.data());
        for (Eigen::Index k = 0; k < no; ++k) ym[static_cast<std::size_t>(k)] = model.output(static_cast<std::size_t>(k), x.data(), up.data());
        up[jj] = u[jj];
        for (Eigen::Index r = 0; r < ns; ++r) {
            const std::size_t s = sys.states[static_cast<std::size_t>(r)];
            sys.B(r, j) = (fp[s] - fm[s]) / (2 * h);
        }
        for (Eigen::Index k = 0; k < no; ++k)
            sys.D(k, j) = (yp[static_cast<std::size_t>(k)] - ym[static_cast<std::size_t>(k)]) / (2 * h);
    }
}

/// C = ∂y/∂x by dual numbers, the states seeded in chunks.
void output_matrix(const NetworkSpec& lin, const NetworkModel<double>& model, const std::vector<double>& params,
                   const CrankAngleChannels* angle_inputs, LinearNetwork& sys) {
    const std::size_t n = lin.nodes.size(), full = 2 * n;
    const std::vector<double>& x = sys.x;
    const std::vector<double>& u = sys.u;
    const auto ns = static_cast<Eigen::Index>(sys.states.size());
    const auto no = static_cast<Eigen::Index>(lin.outputs.size());
    sys.C = Eigen::MatrixXd::Zero(no, ns);
    if (no == 0) return;
    NetworkModel<Dual> dual_model(lin);
    dual_model.set_crank_angle_inputs(angle_inputs);
    std::vector<Dual> dp(params.size()), xd(full);
    for (std::size_t j = 0; j < params.size(); ++j) dp[j] = Dual(params[j]);
    dual_model.set_parameters(dp.data());
    std::vector<Dual> scratch(full);
    for (std::size_t first = 0; first < full; first += kDualCapacity) {
        const std::size_t width = std::min<std::size_t>(kDualCapacity, full - first);
        seed_state_directions(x.data(), full, first, width, xd.data());
        // The element torques an output reads are those of a derivative at the state.
        dual_model.derivative(xd.data(), u.data(), scratch.data());
        for (Eigen::Index k = 0; k < no; ++k) {
            const Dual y = dual_model.output(static_cast<std::size_t>(k), xd.data(), u.data());
            for (Eigen::Index c = 0; c < ns; ++c) {
                const std::size_t s = sys.states[static_cast<std::size_t>(c)];
                for (std::size_t m = first; m < first + width; ++m)  // the column's own state and its tied ones
                    if (const double w = m == s ? 1.0 : tied_column_weight(model, n, s, m); w != 0.0)
                        sys.C(k, c) += w * y.derivative(static_cast<int>(m - first));
            }
        }
    }
}

}  // namespace

LinearNetwork linearise_network(const NetworkSpec& spec, const std::vector<double>& params,
                                const CrankAngleChannels* angle_inputs, const std::vector<double>& x,
                                const std::vector<double>& u, AngleDependence angle_dependence) {
    LinearNetwork sys;
    sys.x = x;
    sys.u = u;
    sys.angle_dependence = angle_dependence;
    const std::size_t n = spec.nodes.size();
    const NetworkSpec lin = linearisation_spec(spec, params, angle_dependence, x, sys.elements, sys.prescribed);

    NetworkModel<double> model(lin);
    model.set_crank_angle_inputs(angle_inputs);
    model.set_parameters(params.data());

    name_states_and_channels(spec, model, u.size(), sys);
    state_matrix(model, n, sys);
    input_matrices(model, n, spec.outputs.size(), sys);
    output_matrix(lin, model, params, angle_inputs, sys);
    return sys;
}

std::vector<std::complex<double>> frequency_response(const LinearNetwork& system, std::size_t input,
                                                     std::size_t output, const std::vector<double>& frequency_hz) {
    using Complex = std::complex<double>;
    constexpr double kTwoPi = 6.283185307179586;
    const auto n = system.A.rows();
    const auto j = static_cast<Eigen::Index>(input), k = static_cast<Eigen::Index>(output);
    const int rate = input < system.rate_of.size() ? system.rate_of[input] : -1;
    std::vector<Complex> h;
    h.reserve(frequency_hz.size());
    const Eigen::MatrixXcd a = system.A.cast<Complex>();
    for (const double f : frequency_hz) {
        const Complex s(0.0, kTwoPi * f);
        // u_rate = s·u: a speed channel's slope enters with its speed.
        Eigen::VectorXcd b = system.B.col(j).cast<Complex>();
        Complex d = system.D(k, j);
        if (rate >= 0) {
            b += s * system.B.col(rate).cast<Complex>();
            d += s * system.D(k, rate);
        }
        const Eigen::MatrixXcd m = s * Eigen::MatrixXcd::Identity(n, n) - a;
        const Eigen::VectorXcd xs = m.fullPivLu().solve(b);
        h.push_back((system.C.row(k).cast<Complex>() * xs)(0) + d);
    }
    return h;
}

}  // namespace tvid

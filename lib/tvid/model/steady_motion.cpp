#include "tvid/model/steady_motion.hpp"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <deque>
#include <type_traits>

#include "tvid/model/damped_newton.hpp"
#include "tvid/model/equilibrium.hpp"

namespace tvid {

namespace {

double value_of(const Field& f, const std::vector<double>& p) {
    return f.is_parameter() ? p[static_cast<std::size_t>(f.parameter)] : f.constant;
}

// ω_a = n · ω_b for an element joining a and b: n its gear ratio, 1 for a shaft.
struct Tie {
    int a, b;
    double ratio;
    const std::string* name;
};

std::vector<Tie> ties(const NetworkSpec& spec, const std::vector<double>& p) {
    std::vector<Tie> out;
    for_each_element(spec, [&](auto kind, const auto& e) {
        // Elastic elements tie their nodes' steady speeds; friction between two nodes lets them slip.
        using Kind = decltype(kind);
        if constexpr (acts_between_nodes<Kind> && Kind::acts_at_rest) {
            if (e.b == kGround) return;
            double n = 1.0;
            if constexpr (Kind::ends == ElementEnds::geared) n = value_of(e.ratio, p);
            out.push_back(Tie{e.a, e.b, n, &e.name});
        }
    });
    return out;
}

}  // namespace

RigidMotion rigid_motion(const NetworkSpec& spec, const std::vector<double>& p, int reference) {
    const std::size_t n = spec.nodes.size();
    RigidMotion m;
    m.ratio.assign(n, 0.0);
    m.tied.assign(n, 0);
    const std::vector<Tie> all = ties(spec, p);
    std::deque<int> queue{reference};
    m.ratio[static_cast<std::size_t>(reference)] = 1.0;
    m.tied[static_cast<std::size_t>(reference)] = 1;
    while (!queue.empty()) {
        const int at = queue.front();
        queue.pop_front();
        for (const Tie& t : all) {
            if (t.a != at && t.b != at) continue;
            const int other = t.a == at ? t.b : t.a;
            const double r = t.a == at ? m.ratio[static_cast<std::size_t>(at)] / t.ratio  // ω_b = ω_a / n
                                       : m.ratio[static_cast<std::size_t>(at)] * t.ratio;
            auto& known = m.ratio[static_cast<std::size_t>(other)];
            if (!m.tied[static_cast<std::size_t>(other)]) {
                known = r;
                m.tied[static_cast<std::size_t>(other)] = 1;
                queue.push_back(other);
            } else if (std::abs(known - r) > 1e-12 * std::abs(known)) {
                m.problem = "the gear ratios around a loop through " + *t.name + " disagree: node " +
                            spec.nodes[static_cast<std::size_t>(other)].name + " would turn at two speeds";
                return m;
            }
        }
    }
    return m;
}

std::vector<double> speeds_through_rigid_ties(const NetworkSpec& spec, const std::vector<double>& p,
                                              const std::vector<double>& largest) {
    const std::size_t n = spec.nodes.size();
    std::vector<double> scale(n, 0.0);
    for (std::size_t m = 0; m < n && m < largest.size(); ++m) {
        if (!(largest[m] > 0)) continue;
        const RigidMotion rigid = rigid_motion(spec, p, static_cast<int>(m));
        if (!rigid.problem.empty()) continue;
        for (std::size_t j = 0; j < n; ++j)
            if (rigid.tied[j]) scale[j] = std::max(scale[j], largest[m] * std::abs(rigid.ratio[j]));
    }
    return scale;
}

SteadyMotion solve_steady_motion(NetworkModel<double>& model, const double* u, int reference, double speed,
                                 double angle) {
    SteadyMotion r;
    const NetworkSpec& spec = model.spec();
    const auto n = static_cast<Eigen::Index>(model.node_count());
    const auto ref = static_cast<Eigen::Index>(reference);
    RigidMotion rigid = rigid_motion(spec, model.parameters(), reference);
    if (!rigid.problem.empty()) {
        r.problem = rigid.problem;
        return r;
    }
    for (Eigen::Index i = 0; i < n; ++i)
        if (!rigid.tied[static_cast<std::size_t>(i)]) {
            r.problem = "node " + spec.nodes[static_cast<std::size_t>(i)].name + " is joined to " +
                        spec.nodes[static_cast<std::size_t>(reference)].name +
                        " by no element: it has no speed in the line's steady motion";
            return r;
        }
    if (const std::string held = held_to_ground(spec); !held.empty()) {
        // Nothing turns steadily against a spring to ground; at rest the start would be the
        // static equilibrium, which the reference's fixed angle and the free α cannot give.
        r.problem = "the line is held to ground by " + held +
                    ": it has no steady motion (at speed 0 its start is the static equilibrium); start from "
                    "initial_state: equilibrium, measured or rest";
        return r;
    }
    r.ratio = rigid.ratio;
    std::vector<double> x(static_cast<std::size_t>(2 * n)), dxdt(x.size());
    const auto ratio = [&](Eigen::Index i) { return rigid.ratio[static_cast<std::size_t>(i)]; };
    for (Eigen::Index i = 0; i < n; ++i) x[static_cast<std::size_t>(n + i)] = ratio(i) * speed;
    // The unknowns z: each node's twist from the rigid position r_i·angle, except the
    // reference's slot, which holds α; the equations: θ_i'' − r_i·α = 0 for every node.
    auto set_angles = [&](const Eigen::VectorXd& z) {
        for (Eigen::Index i = 0; i < n; ++i) x[static_cast<std::size_t>(i)] = ratio(i) * angle + (i == ref ? 0.0 : z[i]);
    };
    NewtonSystem system;
    system.residual = [&](const Eigen::VectorXd& z, Eigen::VectorXd& g) {
        set_angles(z);
        model.derivative(x.data(), u, dxdt.data());
        for (Eigen::Index i = 0; i < n; ++i) g[i] = dxdt[static_cast<std::size_t>(n + i)] - ratio(i) * z[ref];
        // A node an ideal gear ties moves with its group's root: its row is the tie.
        for (Eigen::Index i = 0; i < n; ++i)
            if (model.tied_to_other(static_cast<std::size_t>(i))) g[i] = model.tie_constraint(static_cast<std::size_t>(i), x.data());
    };
    system.state_value = [&](Eigen::Index j, const Eigen::VectorXd& z) { return ratio(j) * angle + z[j]; };
    system.known_columns.resize(static_cast<std::size_t>(n));
    Eigen::VectorXd& alpha_column = system.known_columns[static_cast<std::size_t>(ref)];
    alpha_column.resize(n);
    for (Eigen::Index i = 0; i < n; ++i)  // ∂(θ_i'' − r_i·α)/∂α; a tie holds no α
        alpha_column[i] = model.tied_to_other(static_cast<std::size_t>(i)) ? 0.0 : -ratio(i);
    const NewtonResult solved = solve_damped_newton(system, Eigen::VectorXd::Zero(n));
    switch (solved.status) {
        case NewtonStatus::converged:
            set_angles(solved.z);
            r.found = true;
            r.acceleration = solved.z[ref];
            r.x = x;
            return r;
        case NewtonStatus::singular: {
            std::vector<char> nodes = solved.free_unknowns;
            if (static_cast<std::size_t>(ref) < nodes.size()) nodes[static_cast<std::size_t>(ref)] = 0;  // α's slot
            r.problem = "the line's stiffness matrix is singular in steady motion: " +
                        nodes_without_hold(spec, model.parameters(), nodes) +
                        " no elastic joint to the rest of the line, so no twist carries the torques; give it one, "
                        "or start from initial_state: measured";
            return r;
        }
        case NewtonStatus::not_converged: break;
    }
    r.problem = "Newton's method did not converge to a steady motion (a stiff element's switch, such as a stiff lossy "
                "gear's efficiency at zero power, can stall it); start from initial_state: measured, or estimated "
                "from it";
    return r;
}

std::string held_to_ground(const NetworkSpec& spec) {
    std::string held;
    for_each_element(spec, [&](auto kind, const auto& e) {
        using Kind = decltype(kind);
        if constexpr (acts_between_nodes<Kind> && Kind::acts_at_rest) {  // friction holds nothing at rest
            if (held.empty() && e.b == kGround)
                held = "'" + e.name + "' (node " + spec.nodes[static_cast<std::size_t>(e.a)].name + " to ground)";
        }
        // A position controller pulls its node to an angle: a spring to ground of stiffness kp.
        if constexpr (std::is_same_v<std::decay_t<decltype(e)>, PositionControllerSpec>) {
            if (held.empty() && e.measures == ControlledQuantity::angle)
                held = "the position controller '" + e.name + "' (node " +
                       spec.nodes[static_cast<std::size_t>(e.node)].name + " to its setpoint angle)";
        }
    });
    return held;
}

}  // namespace tvid

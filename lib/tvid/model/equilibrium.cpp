#include "tvid/model/equilibrium.hpp"

#include <Eigen/Dense>
#include <boost/math/tools/roots.hpp>

#include "tvid/model/damped_newton.hpp"
#include <algorithm>
#include <cmath>
#include <limits>

namespace tvid {

std::string nodes_without_hold(const NetworkSpec& spec, const std::vector<double>& p, const std::vector<char>& members) {
    std::vector<std::string> names;
    std::string controllers;
    for (std::size_t i = 0; i < members.size() && i < spec.nodes.size(); ++i) {
        if (!members[i]) continue;
        const std::string& node = spec.nodes[i].name;
        names.push_back(node);
        // A speed_controller NAME is a spring-damper NAME (k = ki) from its node NAME.reference.
        for (const SpringDamperSpec& sd : spec.spring_dampers) {
            if (sd.name + ".reference" != node) continue;
            const double ki = sd.k.is_parameter() ? p[static_cast<std::size_t>(sd.k.parameter)] : sd.k.constant;
            if (ki == 0.0)
                controllers += " (speed_controller " + sd.name + " has ki = 0: a P-only controller holds no twist, "
                               "and its node's steady speed is not its setpoint; give ki > 0)";
        }
    }
    if (names.empty()) return "a node or group of nodes has";
    std::string text = names.size() == 1 ? "node " : "nodes ";
    const std::size_t shown = std::min<std::size_t>(names.size(), 4);
    for (std::size_t i = 0; i < shown; ++i)
        text += (i == 0 ? "" : i + 1 == shown && shown == names.size() ? " and " : ", ") + names[i];
    if (shown < names.size()) text += " and " + std::to_string(names.size() - shown) + " more";
    return text + controllers + (names.size() == 1 ? " has" : " have");
}

namespace {

EquilibriumResult solve_single_node(NetworkModel<double>& model, const double* u) {
    EquilibriumResult r;
    auto torque = [&](double theta) {
        double t = 0.0;
        model.static_torques(&theta, u, &t);
        return t;
    };
    // Expand a bracket around 0 until the net torque changes sign.
    double lo = -1e-3, hi = 1e-3;
    double f_lo = torque(lo), f_hi = torque(hi);
    for (int i = 0; i < 200 && std::isfinite(f_lo) && std::isfinite(f_hi) && f_lo * f_hi > 0; ++i) {
        lo *= 2;
        hi *= 2;
        f_lo = torque(lo);
        f_hi = torque(hi);
    }
    if (!std::isfinite(f_lo) || !std::isfinite(f_hi)) {
        r.problem = "the static torque is not finite";
        return r;
    }
    if (f_lo == 0) { r.found = true; r.theta = {lo}; return r; }
    if (f_hi == 0) { r.found = true; r.theta = {hi}; return r; }
    if (f_lo * f_hi > 0) {
        r.problem = "no angle balances the static torque: node " + model.spec().nodes.front().name +
                    " has no elastic connection to ground; start from initial_state: { kind: steady, … }, measured, or "
                    "{ kind: estimated, from: measured }";
        return r;
    }
    std::uintmax_t max_iter = 200;
    const auto tol = boost::math::tools::eps_tolerance<double>(std::numeric_limits<double>::digits - 2);
    const auto [a, b] = boost::math::tools::toms748_solve(torque, lo, hi, f_lo, f_hi, tol, max_iter);
    r.found = true;
    r.theta = {0.5 * (a + b)};
    return r;
}

EquilibriumResult solve_network(NetworkModel<double>& model, const double* u) {
    EquilibriumResult r;
    const auto n = static_cast<Eigen::Index>(model.node_count());
    NewtonSystem system;
    system.residual = [&](const Eigen::VectorXd& theta, Eigen::VectorXd& f) {
        model.static_torques(theta.data(), u, f.data());
    };
    system.state_value = [](Eigen::Index j, const Eigen::VectorXd& theta) { return theta[j]; };
    const NewtonResult solved = solve_damped_newton(system, Eigen::VectorXd::Zero(n));
    switch (solved.status) {
        case NewtonStatus::converged:
            r.found = true;
            r.theta.assign(solved.z.data(), solved.z.data() + n);
            return r;
        case NewtonStatus::singular:
            r.problem = "the static stiffness matrix is singular: " +
                        nodes_without_hold(model.spec(), model.parameters(), solved.free_unknowns) +
                        " no elastic connection to ground, so no angle balances the torques; start from "
                        "initial_state: { kind: steady, … }, measured or { kind: estimated, from: measured }, which "
                        "let the line turn";
            return r;
        case NewtonStatus::not_converged: break;
    }
    r.problem = "Newton's method did not converge to a static equilibrium";
    return r;
}

}  // namespace

EquilibriumResult solve_equilibrium(NetworkModel<double>& model, const double* u) {
    if (model.node_count() == 1) return solve_single_node(model, u);
    return solve_network(model, u);
}

}  // namespace tvid

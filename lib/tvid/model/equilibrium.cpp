#include "tvid/model/equilibrium.hpp"

#include <Eigen/Dense>
#include <boost/math/tools/roots.hpp>
#include <cmath>
#include <limits>

namespace tvid {

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
        r.problem = "no angle balances the static torque (no elastic connection to ground?)";
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
    Eigen::VectorXd theta = Eigen::VectorXd::Zero(n), f(n), f_trial(n), trial(n);
    Eigen::MatrixXd jac(n, n);
    auto eval = [&](const Eigen::VectorXd& th, Eigen::VectorXd& out) {
        model.static_torques(th.data(), u, out.data());
    };
    eval(theta, f);
    for (int iter = 0; iter < 100; ++iter) {
        const double norm = f.norm();
        if (!std::isfinite(norm)) break;
        // Finite-difference Jacobian of the static torques.
        for (Eigen::Index j = 0; j < n; ++j) {
            trial = theta;
            const double h = 1e-7 * std::max(1.0, std::abs(theta[j]));
            trial[j] += h;
            eval(trial, f_trial);
            jac.col(j) = (f_trial - f) / h;
        }
        const Eigen::FullPivLU<Eigen::MatrixXd> lu(jac);
        if (!lu.isInvertible()) {
            r.problem = "the static stiffness matrix is singular (a node or group of nodes has no "
                        "elastic connection to ground)";
            return r;
        }
        const Eigen::VectorXd step = lu.solve(-f);
        double alpha = 1.0;
        for (int ls = 0; ls < 40; ++ls, alpha *= 0.5) {
            trial = theta + alpha * step;
            eval(trial, f_trial);
            if (std::isfinite(f_trial.norm()) && f_trial.norm() < norm) break;
        }
        theta = trial;
        f = f_trial;
        const double scale = 1.0 + theta.cwiseAbs().maxCoeff();
        if ((alpha * step).cwiseAbs().maxCoeff() <= 1e-14 * scale || f.norm() == 0.0) {
            r.found = true;
            r.theta.assign(theta.data(), theta.data() + n);
            return r;
        }
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

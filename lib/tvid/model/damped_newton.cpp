#include "tvid/model/damped_newton.hpp"

#include <algorithm>
#include <cmath>

namespace tvid {

namespace {

bool known(const NewtonSystem& s, Eigen::Index j) {
    return static_cast<std::size_t>(j) < s.known_columns.size() && s.known_columns[static_cast<std::size_t>(j)].size() > 0;
}

// The unknowns that take part in the Jacobian's null space.
std::vector<char> null_space_members(const Eigen::FullPivLU<Eigen::MatrixXd>& lu) {
    const Eigen::MatrixXd kernel = lu.kernel();
    std::vector<char> members(static_cast<std::size_t>(kernel.rows()), 0);
    for (Eigen::Index c = 0; c < kernel.cols(); ++c) {
        const double largest = kernel.col(c).cwiseAbs().maxCoeff();
        for (Eigen::Index i = 0; i < kernel.rows(); ++i)
            if (std::abs(kernel(i, c)) > 1e-6 * largest) members[static_cast<std::size_t>(i)] = 1;
    }
    return members;
}

}  // namespace

// Converged residuals: a millionth of the start's (the rounding of angles thousands of
// radians large times a stiff element's stiffness stays below it), or below 1e-9 (rad/s²).
constexpr double kResidualShare = 1e-6;
constexpr double kResidualFloor = 1e-9;

NewtonResult solve_damped_newton(const NewtonSystem& system, Eigen::VectorXd z0) {
    NewtonResult r;
    const Eigen::Index n = z0.size();
    Eigen::VectorXd z = std::move(z0), g(n), g_trial(n), trial(n);
    Eigen::MatrixXd& jac = r.jacobian;
    jac.resize(n, n);
    system.residual(z, g);
    const double start_norm = g.norm();
    bool polished = false;
    for (int iter = 0; iter < 100; ++iter) {
        const double norm = g.norm();
        if (!std::isfinite(norm)) break;
        for (Eigen::Index j = 0; j < n; ++j) {
            if (known(system, j)) {
                jac.col(j) = system.known_columns[static_cast<std::size_t>(j)];
                continue;
            }
            trial = z;
            const double h = state_difference_step(system.state_value(j, z));
            trial[j] += h;
            system.residual(trial, g_trial);
            jac.col(j) = (g_trial - g) / h;
        }
        const Eigen::FullPivLU<Eigen::MatrixXd> lu(jac);
        if (!lu.isInvertible()) {
            r.status = NewtonStatus::singular;
            r.free_unknowns = null_space_members(lu);
            r.z = z;
            return r;
        }
        const Eigen::VectorXd step = lu.solve(-g);
        double alpha = 1.0;
        for (int ls = 0; ls < 40; ++ls, alpha *= 0.5) {
            trial = z + alpha * step;
            system.residual(trial, g_trial);
            if (std::isfinite(g_trial.norm()) && g_trial.norm() < norm) break;
        }
        z = trial;
        g = g_trial;
        // Converged to the angles' precision (they may be thousands of radians): one more
        // step, to rounding.
        double angle_step = 0.0, angle_scale = 1.0;
        for (Eigen::Index i = 0; i < n; ++i) {
            if (known(system, i)) continue;
            angle_step = std::max(angle_step, std::abs(alpha * step[i]));
            angle_scale = std::max(angle_scale, std::abs(system.state_value(i, z)));
        }
        if (angle_step <= 1e-14 * angle_scale && !polished) {
            polished = true;
            continue;
        }
        // A step that small is convergence only where the residual went with it: a line
        // search that found no decrease (a kink the differenced Jacobian cannot see, such as
        // a stiff lossy gear's switch of efficiency at zero power) also ends in tiny steps.
        const bool small = g.norm() <= kResidualShare * start_norm || g.norm() <= kResidualFloor;
        if ((polished && small) || g.norm() == 0.0) {
            r.status = NewtonStatus::converged;
            r.z = z;
            return r;
        }
        if (polished) break;
    }
    r.z = z;
    return r;
}

}  // namespace tvid

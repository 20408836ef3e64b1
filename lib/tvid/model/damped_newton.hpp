#pragma once
// The damped Newton solve of the starts (the static equilibrium, the steady motion): the
// unknowns move a network's angles, the Jacobian comes by forward differences with one
// difference-step rule, a step is halved until the residual's norm falls, and the solve
// ends one polishing step after a step below the angles' precision.

#include <Eigen/Dense>
#include <cmath>
#include <functional>
#include <vector>

namespace tvid {

/// The forward-difference step for an unknown that moves a state value x (an angle that
/// may be thousands of radians on a recording's cumulative encoder angle): 1e-7 rad, plus
/// 1e-10 of |x| so that the difference stays above the rounding of x.
inline double state_difference_step(double x) { return 1e-7 + 1e-10 * std::abs(x); }

struct NewtonSystem {
    /// g(z): the residual of the unknowns z (as many as z).
    std::function<void(const Eigen::VectorXd& z, Eigen::VectorXd& g)> residual;
    /// The state value unknown j moves at z (its difference step and the convergence
    /// test scale with it).
    std::function<double(Eigen::Index j, const Eigen::VectorXd& z)> state_value;
    /// Per unknown: its Jacobian column when known exactly (not differenced); empty
    /// vectors are differenced. Unknowns with a known column are not angles: they take no
    /// part in the convergence test.
    std::vector<Eigen::VectorXd> known_columns;
};

enum class NewtonStatus { converged, singular, not_converged };

struct NewtonResult {
    NewtonStatus status = NewtonStatus::not_converged;
    Eigen::VectorXd z;          ///< the solution (or where the solve stopped)
    Eigen::MatrixXd jacobian;   ///< the last Jacobian (singular: the one that was)
    /// singular: per unknown, whether it takes part in a direction the Jacobian maps to 0
    /// (those unknowns have no elastic hold).
    std::vector<char> free_unknowns;
};

/// Damped Newton from z0, at most 100 steps. Never throws.
NewtonResult solve_damped_newton(const NewtonSystem& system, Eigen::VectorXd z0);

}  // namespace tvid

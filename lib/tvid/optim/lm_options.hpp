#pragma once
// Options of the Levenberg–Marquardt least-squares solver (levenberg_marquardt.hpp).
// The tolerances follow MINPACK's lmder (Moré 1978): they are relative and work on the
// parameters scaled by D = diag(column norms of the Jacobian), so they mean the same
// whether a parameter is an inertia of 1e-3 kg m² or a stiffness of 1e5 N m/rad.

#include "tvid/optim/settings_problem.hpp"

namespace tvid {

struct LmSettings {
    /// Trial steps (each one linear solve and one residual evaluation, accepted or not).
    int max_iterations = 200;
    /// Converged when an accepted step changes the cost by less than ftol relative to it,
    /// both as measured and as predicted by the linear model (MINPACK's ftol test).
    double ftol = 1e-10;
    /// Converged when the scaled step is small: ‖D s‖ < xtol (‖D x‖ + xtol).
    double xtol = 1e-10;
    /// Converged when the scaled gradient is small over the free parameters:
    /// max_j |J_jᵀ r| / (‖J_j‖ ‖r‖) < gtol, the cosine between r and each column (MINPACK).
    double gtol = 1e-10;
    /// Converged when the optimum is within stol standard errors of the current point: the
    /// Gauss–Newton model's whole achievable decrease of Σr² over the free parameters (‖r‖²
    /// projected on the Jacobian's columns) is below stol²·σ², σ² = Σr²/(N − M) the
    /// residuals' variance. That decrease is the squared Mahalanobis distance to the
    /// linearised optimum in units of σ², so every combination of the parameters is then
    /// within stol of its standard error: steps beyond it move nothing the data can tell.
    /// Noise-free data (σ → 0) meet it only at the exact optimum. 0: no statistical test.
    double stol = 0.1;
    /// τ in Moré's / Nielsen's start λ0 = τ · max_j (JᵀJ)_jj / d_j², i.e. relative to the
    /// diagonal of the scaled JᵀJ (its largest entry is 1 on the first iteration). Must be > 0.
    double initial_damping = 1e-3;
    /// Give up with "no progress" after this many rejected steps in a row (e.g. a model
    /// whose simulation fails everywhere around the current point).
    int max_consecutive_rejections = 20;
};

/// The first problem of the settings, or none.
std::optional<SettingsProblem> validate(const LmSettings& settings);

}  // namespace tvid

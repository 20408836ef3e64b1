#pragma once
// Levenberg–Marquardt nonlinear least squares with bounds (the methodology paper uses LM for the
// engine-block fit): minimize ½‖r(x)‖² over lower ≤ x ≤ upper.
//
// The shape is Ceres-like: a LeastSquaresProblem (the residuals and their Jacobian) is
// separate from the solver; LmSettings go in, an LmSummary comes out. The solver knows
// nothing of models: a fit wraps its simulation in a LeastSquaresProblem.
//
// Algorithm (details in levenberg_marquardt.cpp):
//  * Moré's diagonal scaling D = diag(d_j), d_j = max over iterations of ‖J_j‖ (MINPACK
//    lmder), so parameters of very different magnitude converge alike;
//  * step from the damped least-squares system  min ‖J p + r‖² + λ ‖D p‖², solved by a QR
//    of J once per Jacobian and a small QR of [R; √λ D] per trial (no normal equations);
//  * bounds by an active set (a parameter on a bound whose gradient, or whose step,
//    points outward is held for that step); a parameter whose step would cross a bound is
//    put on it and the others' step solved again for that displacement, so every iterate
//    is feasible, a step along a bound is the model's best one there, and an optimum on a
//    bound is reached exactly;
//  * gain ratio ρ = actual / predicted reduction: accept when ρ > 1e-4, Nielsen's update
//    of λ (λ·max(1/3, 1 − (2ρ − 1)³) on success, λ·ν with ν doubling on failure);
//  * a failed evaluation (false or non-finite residuals) is a rejected step;
//  * a problem that evaluates residuals side by side gets the current trial together with
//    the trials of the next rejections (λν, λν·2ν, ...): the iterates are the same as one
//    at a time, a rejection only costs no wall time.

#include <Eigen/Core>
#include <cstddef>
#include <functional>
#include <string>
#include <vector>

#include "tvid/optim/lm_options.hpp"
#include "tvid/optim/optimizer_summary.hpp"
#include "tvid/optim/termination.hpp"

namespace tvid {

/// Residuals r(x) (N values) of M parameters and optionally their Jacobian.
class LeastSquaresProblem {
public:
    virtual ~LeastSquaresProblem() = default;
    /// N, the number of residuals (constant for the life of the problem).
    virtual std::size_t residual_count() const = 0;
    /// r(x) into r[0..N). false when the model cannot be evaluated at x (e.g. its
    /// simulation diverged): the solver takes that as a bad step, never a crash.
    virtual bool residuals(const double* x, double* r) = 0;
    /// r and the N×M Jacobian J = ∂r/∂x (column-major) at x; false on failure. J arrives
    /// sized N×M. The r returned must be the one residuals() gives at the same x.
    virtual bool jacobian(const double* x, double* r, Eigen::MatrixXd& J) = 0;
    /// True when the last residuals()/jacobian() returned false because a stop request
    /// (Ctrl-C) cut it short, not because the model failed: the solver stops at its
    /// current point instead of counting a failed step.
    virtual bool stopped() const { return false; }
    /// Why the model cannot be evaluated at x, as one line for the report (e.g. which
    /// simulation failed, where and when, and what to try); empty when the problem cannot
    /// say. Asked once, when the start itself fails.
    virtual std::string failure(const double* /*x*/) { return {}; }
    /// How many residual evaluations residuals_side_by_side() runs at once (1: one after
    /// the other). The solver then evaluates, next to each trial step, the steps that the
    /// next rejections would take, so a rejection costs no wall time.
    virtual int concurrent_residuals() const { return 1; }
    /// The most concurrent_residuals() will ever say (it may change between calls: a batch
    /// job's share of the cores grows as the batch ends).
    virtual int max_concurrent_residuals() const { return concurrent_residuals(); }
    /// r(x[k]) into r[k] for k < count: ok[k] as residuals() returns it and stopped[k] as
    /// stopped() would say right after it. The results must be those of residuals() at
    /// each point alone, and a later jacobian() at any of the points may reuse them.
    virtual void residuals_side_by_side(std::size_t count, const double* const* x, double* const* r, char* ok,
                                        char* stopped) {
        for (std::size_t k = 0; k < count; ++k) {
            ok[k] = residuals(x[k], r[k]) ? 1 : 0;
            stopped[k] = !ok[k] && this->stopped() ? 1 : 0;
        }
    }
    /// Model simulations run so far when the problem counts them (a Jacobian may take
    /// several); -1 when it does not (drivers then count residual and Jacobian calls).
    virtual long long simulations() const { return -1; }
    /// Right-hand sides of the model evaluated so far (0 where not counted).
    virtual long long right_hand_sides() const { return 0; }
};

/// Levenberg–Marquardt's summary: best is the last accepted point (the lowest cost seen);
/// best_cost Σ r² there, the l2 cost of the rest of the tool (the methodology paper eq. 7),
/// i.e. twice the ½‖r‖² the solver minimizes internally, +inf when the start could not be
/// evaluated; iterations the trial steps taken (accepted and rejected); evaluations the
/// residual and Jacobian evaluations; failed_evaluations the calls that returned false or
/// non-finite values; history one row per iteration (row 0 the start, row k after trial
/// step k; `evaluations` counts residual + Jacobian evaluations, `best_cost` is Σ r², never
/// increasing); termination "cost change below ftol", "step below xtol", "gradient below
/// gtol" (converged), "iteration limit", "stopped" (the progress callback returned false,
/// or the problem was stopped mid-evaluation), "no progress" (max_consecutive_rejections
/// rejected steps in a row, or the only steps that evaluate are below xtol because the
/// model fails just beyond the current point: stuck at the edge of a region where e.g. the
/// simulation diverges), "start failed"; success: converged.
struct LmSummary : OptimizerSummary {
    LmSummary() { termination_type = TerminationType::converged; }
    double initial_cost = 0.0;           ///< Σ r² at the (projected) start
    long long residual_evaluations = 0;  ///< residual evaluations of trial steps taken
    /// Trial steps evaluated ahead, side by side with the step taken, for the damping that
    /// rejections would lead to (concurrent_residuals() > 1), and how many of them a
    /// rejection then took (those count in residual_evaluations too).
    long long evaluated_ahead = 0, taken_ahead = 0;
    long long jacobian_evaluations = 0;  ///< jacobian() calls (the start counts one)
    Eigen::MatrixXd jacobian_at_best;    ///< N×M at `best`; empty when the start failed
};

/// Called after the start and after every iteration; return false to stop (e.g. Ctrl-C).
using LmProgress = std::function<bool(const HistoryRow&)>;

/// Minimize ½‖r(x)‖² subject to lower ≤ x ≤ upper, starting from x0 (projected on the box).
/// A bound of ±1e300 or ±inf means none. Throws std::invalid_argument on inconsistent sizes,
/// lower > upper, a non-finite start or invalid settings; never for a failed evaluation.
LmSummary run_levenberg_marquardt(const LmSettings& settings, std::vector<double> x0,
                                  const std::vector<double>& lower, const std::vector<double>& upper,
                                  LeastSquaresProblem& problem, const LmProgress& progress = {});

class ParameterScaling;
/// The summary of a run in search coordinates (parameter_scaling.hpp) as parameters: its
/// best point, and its Jacobian there as ∂r/∂p.
void to_parameters(const ParameterScaling& scaling, LmSummary& summary);

}  // namespace tvid

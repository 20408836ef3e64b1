#pragma once
// A fixed-step implicit method for stiff models at the recording's own step: Alexander's
// (1977) three-stage SDIRK of order 3, L-stable and stiffly accurate (the last stage is the
// step's result). Each stage Z_i = x + h Σ_j<i a_ij K_j + hγ K_i, K_i = f(Z_i, u(t + c_i h)),
// is solved by simplified Newton iterations on the model's exact state Jacobian
// (StateJacobian, dual numbers), refreshed when they converge slowly, with a backtracking
// guard. A stiff mode (a sticking dry friction, a stiff
// spring on a small inertia) then decays within a step as it physically does instead of
// limiting the step, which stays the sample interval (split only by simulation.step).
//
// Sensitivities are those of the discrete method itself, as RK4's are through its stages:
// with S = ∂x/∂q, differentiating stage i gives
//   (I − hγ J(Z_i)) dK_i = J(Z_i) E_i + ∂f/∂q,   E_i = S + h Σ_j<i a_ij dK_j,
// whose right side is one dual-number pass of f at Z_i carrying E_i as its derivatives, and
// then S' = E_3 + hγ dK_3. A step whose Newton iterations do not converge is split in halves
// (at most kMaxHalvings times) before the simulation gives up.

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <limits>
#include <vector>

#include "tvid/channels/input_channels.hpp"
#include "tvid/model/dual.hpp"
#include "tvid/model/network_model.hpp"
#include "tvid/model/state_jacobian.hpp"
#include "tvid/sim/observation_loops.hpp"
#include "tvid/sim/simulation_status.hpp"

namespace tvid {

/// Alexander's L-stable SDIRK3 (Hairer & Wanner, Solving ODEs II, table IV.6.5): γ is the
/// root of x³ − 3x² + 3x/2 − 1/6 in (1/3, 1/2); the last row of A is b.
struct Sdirk3Tableau {
    static constexpr double gamma = 0.43586652150845899941601945;
    static constexpr double b1 = -(6 * gamma * gamma - 16 * gamma + 1) / 4;
    static constexpr double b2 = (6 * gamma * gamma - 20 * gamma + 5) / 4;
    static constexpr double a[3][3] = {{gamma, 0, 0}, {(1 - gamma) / 2, gamma, 0}, {b1, b2, gamma}};
    static constexpr double c[3] = {gamma, (1 + gamma) / 2, 1.0};
};

class Sdirk3 {
public:
    static constexpr int kMaxNewtonIterations = 30;
    /// The shortest fraction of a Newton update the backtracking tries.
    static constexpr double kSmallestFraction = 1.0 / 256;
    static constexpr int kMaxHalvings = 6;
    /// A stage counts as solved when every Newton update is below this share of its state's
    /// scale (the larger of the state and the largest it has been in this simulation).
    static constexpr double kNewtonTolerance = 1e-10;

    /// Follows `model` (its parameters as set) over `inputs`; sensitivities off.
    void bind(NetworkModel<double>& model, const InputChannels& inputs) {
        model_ = &model;
        inputs_ = &inputs;
        jacobian_.bind(model);
        n_ = model.state_size();
        const auto n = static_cast<Eigen::Index>(n_);
        base_.resize(n), z_.resize(n), f_.resize(n), r_.resize(n), delta_.resize(n), z_before_.resize(n);
        scale_.resize(n);
        for (Eigen::VectorXd& k : k_) k.resize(n);
        j_.resize(n_ * n_);
        j_stage_.resize(n_ * n_);
        m_.resize(n, n);
        u_.resize(inputs.count());
        dual_ = nullptr;
        d_ = 0;
        guess_known_ = false;
        hint_ = 0;
    }

    /// Sensitivities along `directions` parameter directions: `dual` is the model with its
    /// parameters seeded along them, `x`, `f` scratch of the state size.
    void bind_sensitivities(NetworkModel<Dual>& dual, int directions, std::vector<Dual>& x, std::vector<Dual>& f) {
        dual_ = &dual;
        d_ = static_cast<std::size_t>(directions);
        xd_ = &x;
        fd_ = &f;
        const auto n = static_cast<Eigen::Index>(n_), d = static_cast<Eigen::Index>(d_);
        e_.resize(n, d), g_.resize(n, d), s_next_.resize(n, d);
        for (Eigen::MatrixXd& dk : dk_) dk.resize(n, d);
    }

    /// The scale of each state at the simulation's start (the Newton tolerance's floor).
    void begin(const double* x) {
        for (std::size_t i = 0; i < n_; ++i) scale_[static_cast<Eigen::Index>(i)] = std::abs(x[i]);
        guess_known_ = false;
        stale_ = true;
        factored_hg_ = 0.0;
    }

    /// The sampled elements (NetworkModel::samples) restarted at the simulation's start and
    /// sampled at each later sample, in the model (its outputs) and in the Jacobian's (f).
    void restart_sampling(const double* x, const double* u) {
        model_->restart_sampling(x, u);
        jacobian_.restart_sampling(x, u);
    }
    void sample(double t, const double* x, const double* u) {
        model_->sample(t, x, u);
        jacobian_.sample(t, x, u);
    }

    /// Crosses sample interval i of `time` in steps of at most max_step (0: one step): x the
    /// state, s its sensitivities (n × directions, row-major; null without sensitivities).
    SimulationStatus cross(const std::vector<double>& time, std::size_t i, double max_step, double* x, double* s) {
        const double t0 = time[i], h = time[i + 1] - t0;
        const double count = substeps_over(h, max_step);
        if (!(count <= kMaxFixedStepsPerSimulation)) return SimulationStatus::step_budget_exceeded;
        const int substeps = static_cast<int>(count);
        const double dt = h / substeps;
        for (int k = 0; k < substeps; ++k) {
            const SimulationStatus status = advance(t0 + k * dt, dt, x, s, 0);
            if (status != SimulationStatus::ok) return status;
        }
        return SimulationStatus::ok;
    }

    std::size_t rhs_evaluations = 0;       ///< f (Newton iterations), running total
    std::size_t jacobian_evaluations = 0;  ///< ∂f/∂x, running total
    std::size_t steps = 0;              ///< steps taken, running total
    std::size_t halvings = 0;           ///< steps split because Newton did not converge

private:
    using RowMajor = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;

    SimulationStatus advance(double t, double h, double* x, double* s, int depth) {
        if (step(t, h, x, s)) return SimulationStatus::ok;
        for (std::size_t i = 0; i < n_; ++i)
            if (!std::isfinite(x[i])) return SimulationStatus::not_finite;
        if (depth >= kMaxHalvings) return failure_;
        ++halvings;
        const SimulationStatus first = advance(t, h / 2, x, s, depth + 1);
        return first != SimulationStatus::ok ? first : advance(t + h / 2, h / 2, x, s, depth + 1);
    }

    // One step of h from t; x (and s) change only when every stage is solved.
    bool step(double t, double h, double* x, double* s) {
        using T = Sdirk3Tableau;
        const Eigen::Map<const Eigen::VectorXd> x0(x, static_cast<Eigen::Index>(n_));
        for (int i = 0; i < 3; ++i) {
            base_ = x0;
            for (int j = 0; j < i; ++j) base_ += (h * T::a[i][j]) * k_[j];
            const Eigen::VectorXd* guess = i > 0 ? &k_[i - 1] : guess_known_ ? &k_[2] : nullptr;
            if (!solve_stage(t + T::c[i] * h, h * T::gamma, guess)) return false;
            k_[i] = (z_ - base_) / (h * T::gamma);  // the stage's slope as the Newton solution implies it
            if (dual_ && s && !stage_sensitivity(i, h, s)) return false;
        }
        ++steps;
        std::copy(z_.data(), z_.data() + n_, x);  // stiffly accurate: the last stage is the step
        for (std::size_t i = 0; i < n_; ++i)
            scale_[static_cast<Eigen::Index>(i)] = std::max(scale_[static_cast<Eigen::Index>(i)], std::abs(x[i]));
        guess_known_ = true;
        if (dual_ && s) {
            Eigen::Map<RowMajor>(s, static_cast<Eigen::Index>(n_), static_cast<Eigen::Index>(d_)) = s_next_;
        }
        return true;
    }

    // Simplified Newton on F(Z) = Z − base − hγ f(Z, u(t)) = 0 from Z = base + hγ·guess (or
    // base): f in doubles at every iterate, the Jacobian kept from stage to stage and step to
    // step (γ is the same in all three stages, h in all steps: so is the LU of I − hγ J) and
    // evaluated afresh at the current iterate when the updates stop shrinking fast or the
    // residual grows (then also stepping back along the last update).
    // Leaves Z in z_.
    bool solve_stage(double t, double hg, const Eigen::VectorXd* guess) {
        inputs_->at(t, hint_, u_.data());
        z_ = base_;
        if (guess) z_ += hg * *guess;
        const auto n = static_cast<Eigen::Index>(n_);
        double floor = 0.0;
        for (Eigen::Index i = 0; i < n; ++i) floor = std::max(floor, scale_[i]);
        floor *= 1e-4 * kNewtonTolerance;  // a state still at zero: a tolerance far below every other's
        const auto weighted = [&](const Eigen::VectorXd& v) {
            double worst = 0.0;
            for (Eigen::Index i = 0; i < n; ++i) {
                const double tol = kNewtonTolerance * std::max(std::abs(z_[i]), scale_[i]) + floor;
                const double ratio = tol > 0 ? std::abs(v[i]) / tol : (v[i] == 0 ? 0.0 : std::numeric_limits<double>::infinity());
                worst = std::max(worst, ratio);
            }
            return worst;
        };
        double residual_before = std::numeric_limits<double>::infinity(), update_before = 0.0, lambda = 1.0;
        for (int it = 0; it < kMaxNewtonIterations; ++it) {
            ++rhs_evaluations;
            model_->derivative(z_.data(), u_.data(), f_.data());
            r_ = z_ - base_ - hg * f_;
            if (!r_.allFinite()) {
                failure_ = SimulationStatus::not_finite;
                return false;
            }
            const double residual = weighted(r_);
            if (residual > residual_before && lambda > kSmallestFraction) {  // the update overshot: back along it
                lambda /= 4;
                z_ = z_before_ + lambda * delta_;
                stale_ = true;
                continue;
            }
            if (stale_) {
                if (!evaluate_jacobian(z_, j_)) return false;
                stale_ = false;
                factored_hg_ = 0.0;
            }
            if (hg != factored_hg_) {  // a new Jacobian, or a halved step
                factor(j_, hg, lu_);
                factored_hg_ = hg;
            }
            delta_.noalias() = lu_.solve(-r_);
            if (!delta_.allFinite()) {
                failure_ = SimulationStatus::not_finite;
                return false;
            }
            const double update = weighted(delta_);
            z_before_ = z_;
            residual_before = residual;
            lambda = 1.0;
            z_ += delta_;
            // Solved: below the tolerance, or no longer shrinking at rounding's level.
            const bool slow = it > 0 && update > 0.5 * update_before;
            if (update <= 1.0 || (slow && update <= 1e2)) return true;
            if (slow) stale_ = true;
            update_before = update;
        }
        failure_ = SimulationStatus::step_budget_exceeded;
        return false;
    }

    // J = ∂f/∂x at z and the current stage's inputs into `j` (row-major).
    bool evaluate_jacobian(const Eigen::VectorXd& z, std::vector<double>& j) {
        ++jacobian_evaluations;
        jacobian_.evaluate(z.data(), u_.data(), j.data());
        for (const double v : j)
            if (!std::isfinite(v)) {
                failure_ = SimulationStatus::not_finite;
                return false;
            }
        return true;
    }

    // The LU of I − hγ J into `lu`.
    void factor(const std::vector<double>& j, double hg, Eigen::PartialPivLU<Eigen::MatrixXd>& lu) {
        const auto n = static_cast<Eigen::Index>(n_);
        m_.noalias() = -hg * Eigen::Map<const RowMajor>(j.data(), n, n);
        m_.diagonal().array() += 1.0;
        lu.compute(m_);
    }

    // dK_i from the stage's Jacobian; on the last stage S' = E_3 + hγ dK_3.
    bool stage_sensitivity(int i, double h, const double* s) {
        using T = Sdirk3Tableau;
        const auto n = static_cast<Eigen::Index>(n_), d = static_cast<Eigen::Index>(d_);
        e_ = Eigen::Map<const RowMajor>(s, n, d);
        for (int j = 0; j < i; ++j) e_ += (h * T::a[i][j]) * dk_[j];
        std::vector<Dual>& xd = *xd_;
        for (Eigen::Index k = 0; k < n; ++k) {
            Dual& v = xd[static_cast<std::size_t>(k)];
            v.set_value(z_[k]);
            v.resize(static_cast<int>(d));
            for (Eigen::Index j = 0; j < d; ++j) v.derivatives()[j] = e_(k, j);
        }
        dual_->derivative(xd.data(), u_.data(), fd_->data());
        for (Eigen::Index k = 0; k < n; ++k) {
            const Dual& f = (*fd_)[static_cast<std::size_t>(k)];
            for (Eigen::Index j = 0; j < d; ++j) g_(k, j) = f.derivative(static_cast<int>(j));
        }
        if (!evaluate_jacobian(z_, j_stage_)) return false;  // at the stage itself: exact
        factor(j_stage_, h * T::gamma, stage_lu_);
        dk_[i].noalias() = stage_lu_.solve(g_);
        if (!dk_[i].allFinite()) {
            failure_ = SimulationStatus::not_finite;
            return false;
        }
        if (i == 2) s_next_ = e_ + (h * T::gamma) * dk_[2];
        return true;
    }

    NetworkModel<double>* model_ = nullptr;
    const InputChannels* inputs_ = nullptr;
    StateJacobian jacobian_;
    std::size_t n_ = 0, d_ = 0, hint_ = 0;
    Eigen::VectorXd base_, z_, f_, r_, delta_, z_before_, scale_;
    Eigen::VectorXd k_[3];
    std::vector<double> j_, j_stage_, u_;  ///< Newton's Jacobian (kept over steps), the stage's
    Eigen::MatrixXd m_;
    Eigen::PartialPivLU<Eigen::MatrixXd> lu_, stage_lu_;  ///< Newton's, the sensitivities'
    double factored_hg_ = 0.0;                           ///< the hγ of lu_ (0: none)
    bool guess_known_ = false, stale_ = true;
    SimulationStatus failure_ = SimulationStatus::ok;
    // Sensitivities.
    NetworkModel<Dual>* dual_ = nullptr;
    std::vector<Dual>*xd_ = nullptr, *fd_ = nullptr;
    Eigen::MatrixXd e_, g_, s_next_;
    Eigen::MatrixXd dk_[3];
};

}  // namespace tvid

#include "tvid/sim/sdirk3.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "tvid/sim/observation_loops.hpp"

namespace tvid {

void Sdirk3::bind(NetworkModel<double>& model, const InputChannels& inputs) {
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

void Sdirk3::bind_sensitivities(NetworkModel<Dual>& dual, int directions, std::vector<Dual>& x, std::vector<Dual>& f) {
    dual_ = &dual;
    d_ = static_cast<std::size_t>(directions);
    xd_ = &x;
    fd_ = &f;
    const auto n = static_cast<Eigen::Index>(n_), d = static_cast<Eigen::Index>(d_);
    e_.resize(n, d), g_.resize(n, d), s_next_.resize(n, d);
    for (Eigen::MatrixXd& dk : dk_) dk.resize(n, d);
}

void Sdirk3::begin(const double* x) {
    for (std::size_t i = 0; i < n_; ++i) scale_[static_cast<Eigen::Index>(i)] = std::abs(x[i]);
    guess_known_ = false;
    stale_ = true;
    factored_hg_ = 0.0;
}

SimulationStatus Sdirk3::cross(const std::vector<double>& time, std::size_t i, double max_step, double* x, double* s) {
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

SimulationStatus Sdirk3::advance(double t, double h, double* x, double* s, int depth) {
    if (step(t, h, x, s)) return SimulationStatus::ok;
    for (std::size_t i = 0; i < n_; ++i)
        if (!std::isfinite(x[i])) return SimulationStatus::not_finite;
    if (depth >= kMaxHalvings) return failure_;
    ++halvings;
    const SimulationStatus first = advance(t, h / 2, x, s, depth + 1);
    return first != SimulationStatus::ok ? first : advance(t + h / 2, h / 2, x, s, depth + 1);
}

bool Sdirk3::step(double t, double h, double* x, double* s) {
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

bool Sdirk3::solve_stage(double t, double hg, const Eigen::VectorXd* guess) {
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
        const bool slow = it > 0 && update > kRefreshRate * update_before;
        if (update <= 1.0 || (slow && update <= 1e2)) return true;
        if (slow) stale_ = true;
        update_before = update;
    }
    failure_ = SimulationStatus::step_budget_exceeded;
    return false;
}

bool Sdirk3::evaluate_jacobian(const Eigen::VectorXd& z, std::vector<double>& j) {
    ++jacobian_evaluations;
    jacobian_.evaluate(z.data(), u_.data(), j.data());
    for (const double v : j)
        if (!std::isfinite(v)) {
            failure_ = SimulationStatus::not_finite;
            return false;
        }
    return true;
}

void Sdirk3::factor(const std::vector<double>& j, double hg, Eigen::PartialPivLU<Eigen::MatrixXd>& lu) {
    const auto n = static_cast<Eigen::Index>(n_);
    m_.noalias() = -hg * Eigen::Map<const RowMajor>(j.data(), n, n);
    m_.diagonal().array() += 1.0;
    lu.compute(m_);
}

bool Sdirk3::stage_sensitivity(int i, double h, const double* s) {
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

}  // namespace tvid

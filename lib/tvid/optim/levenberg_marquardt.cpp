#include "tvid/optim/levenberg_marquardt.hpp"

#include "tvid/optim/parameter_scaling.hpp"

#include <Eigen/QR>
#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

namespace tvid {

namespace {

constexpr double kAcceptRatio = 1e-4;  // accept a step when ρ exceeds this (MINPACK's 1e-4)
constexpr double kMinDamping = 1e-32;  // λ relative to a scaled JᵀJ whose diagonal is ≤ 1: below it is 0
// Trial steps evaluated side by side at most: the current one and the next three
// rejections' (longer runs of rejections are rare; each ahead is work lost on acceptance).
constexpr int kMaxTrialsSideBySide = 4;
// The statistical cost test's steps count only while the Gauss–Newton model promises at most
// this many σ² more (its linearised optimum within 5 standard errors): near a minimum, where
// Σr²/(N − M) is the noise. The shipped fits' settled steps promise 0.16-8.6 σ² (the engine
// 2.3-2.7, the measured bench's runs up to 8.6); a start far off promises about N − M.
constexpr double kSettledReducible = 25.0;

using Eigen::Index;

void check_arguments(const LmSettings& settings, const std::vector<double>& x0, const std::vector<double>& lower,
                     const std::vector<double>& upper, std::size_t residual_count) {
    if (x0.empty()) throw std::invalid_argument("Levenberg-Marquardt: no free parameters");
    if (lower.size() != x0.size() || upper.size() != x0.size())
        throw std::invalid_argument("Levenberg-Marquardt: bounds and start differ in size");
    if (residual_count == 0) throw std::invalid_argument("Levenberg-Marquardt: the problem has no residuals");
    for (std::size_t j = 0; j < x0.size(); ++j) {
        if (!std::isfinite(x0[j])) throw std::invalid_argument("Levenberg-Marquardt: non-finite start value");
        if (!(lower[j] <= upper[j])) throw std::invalid_argument("Levenberg-Marquardt: lower bound above upper bound");
    }
    if (settings.max_iterations < 0 || settings.max_consecutive_rejections < 1)
        throw std::invalid_argument("Levenberg-Marquardt: iteration limits must be positive");
    if (!(settings.ftol >= 0) || !(settings.xtol >= 0) || !(settings.gtol >= 0) || !(settings.stol >= 0))
        throw std::invalid_argument("Levenberg-Marquardt: tolerances must not be negative");
    if (!(settings.initial_damping > 0) || !std::isfinite(settings.initial_damping))
        throw std::invalid_argument("Levenberg-Marquardt: the initial damping must be positive");
}

// r and J at x into the given buffers; false when the problem fails or returns non-finite values.
bool evaluate_jacobian(LeastSquaresProblem& problem, const Eigen::VectorXd& x, Eigen::VectorXd& r,
                       Eigen::MatrixXd& J) {
    const Index n = r.size(), m = x.size();
    J.resize(n, m);  // no-op unless a failed call left it resized
    if (!problem.jacobian(x.data(), r.data(), J)) return false;
    if (J.rows() != n || J.cols() != m)
        throw std::logic_error("Levenberg-Marquardt: the problem returned a Jacobian of the wrong size");
    return r.allFinite() && J.allFinite();
}

// The damped step for one λ (Moré 1978, eq. 2.3 in scaled form):
//   min_p ‖R p + Qᵀr‖² + λ ‖D p‖²,   p_j = 0 for the held parameters,
// which equals min ‖J p + r‖² + λ‖D p‖² because J = Q R. Solved as the 2M×M least-squares
// problem [R; √λ D] p ≅ [−Qᵀr; 0] by Householder QR: the conditioning of J, not of JᵀJ.
// A held parameter's column of R is zeroed, which leaves it only the row √λ d_j p_j = 0.
class DampedStep {
public:
    explicit DampedStep(Index m) : m_(m), a_(2 * m, m), b_(2 * m), qr_(2 * m, m) {}

    void solve(const Eigen::MatrixXd& R, const Eigen::VectorXd& qtr, const Eigen::VectorXd& scale, double lambda,
               const std::vector<char>& held, Eigen::VectorXd& p) {
        a_.setZero();
        const double root = std::sqrt(lambda);
        for (Index c = 0; c < m_; ++c) {
            if (!held[static_cast<std::size_t>(c)]) a_.col(c).head(c + 1) = R.col(c).head(c + 1);
            a_(m_ + c, c) = root * scale[c];
        }
        b_.head(m_) = -qtr;
        b_.tail(m_).setZero();
        qr_.compute(a_);
        b_.applyOnTheLeft(qr_.householderQ().adjoint());
        p = b_.head(m_);
        qr_.matrixQR().topLeftCorner(m_, m_).triangularView<Eigen::Upper>().solveInPlace(p);
        for (Index c = 0; c < m_; ++c)
            if (held[static_cast<std::size_t>(c)]) p[c] = 0.0;
    }

private:
    Index m_;
    Eigen::MatrixXd a_;
    Eigen::VectorXd b_;
    Eigen::HouseholderQR<Eigen::MatrixXd> qr_;
};

// One run of the solver as a loop of named steps, in the shape of a trust-region
// minimizer (Ceres' TrustRegionMinimizer): iteration zero at the start; then, each
// iteration, the new Jacobian's set-up (scaling, active set, gradient test, QR), the trial
// step for the current damping, the trial point's evaluation, its acceptance or
// rejection, the damping update, the history row and the convergence tests.
class LevenbergMarquardt {
public:
    LevenbergMarquardt(const LmSettings& settings, const std::vector<double>& x0, const std::vector<double>& lower,
                       const std::vector<double>& upper, LeastSquaresProblem& problem, const LmProgress& progress)
        : settings_(settings),
          problem_(problem),
          progress_(progress),
          m_(static_cast<Index>(x0.size())),
          n_(static_cast<Index>(problem.residual_count())),
          lo_(m_), hi_(m_), x_(m_), x_trial_(m_),
          r_(n_), r_trial_(n_), qtr_full_(n_),
          J_(n_, m_), J_trial_(n_, m_),
          gradient_(m_), column_norm_(m_), d_(Eigen::VectorXd::Zero(m_)), scale_(m_),
          p_(m_), step_(m_), qtr_(m_), Rs_(m_),
          R_(Eigen::MatrixXd::Zero(m_, m_)),
          qr_j_(n_, m_),
          damped_(m_),
          held_(x0.size(), 0), held_trial_(x0.size(), 0), on_bound_(x0.size(), 0),
          to_bound_(m_), qtr_on_bound_(m_), ahead_step_(m_) {
        // Everything the iterations touch is allocated here, once.
        for (Index j = 0; j < m_; ++j) {
            const auto u = static_cast<std::size_t>(j);
            lo_[j] = lower[u];
            hi_[j] = upper[u];
            x_[j] = std::clamp(x0[u], lo_[j], hi_[j]);  // start feasible
        }
        s_.best.assign(x0.size(), 0.0);
        s_.history.reserve(static_cast<std::size_t>(std::min(settings.max_iterations, 1 << 16)) + 1);
    }

    LmSummary minimize() {
        if (!iteration_zero()) return std::move(s_);
        set_up_trials_ahead();
        while (iteration()) {
        }
        keep_current_point();
        return std::move(s_);
    }

private:
    struct TrialStep {
        bool finite = false, moves = false;
        double predicted = 0.0;  // the reduction of ½‖r‖² that the linear model predicts
    };
    struct TrialPoint {
        bool evaluable = false;
        bool halted = false;  // a stop request cut its evaluation short
        double f = 0.0;       // ½‖r‖² there (the current f when not evaluated)
    };
    // A trial evaluated ahead, side by side with an earlier one (evaluate_with_ahead).
    struct AheadTrial {
        Eigen::VectorXd x, r;
        bool ok = false;
    };
    enum class Acceptance { accepted, failed, stopped };

    // The end of the run at the current point.
    void finish(TerminationType type, const std::string& reason) {
        for (Index j = 0; j < m_; ++j) s_.best[static_cast<std::size_t>(j)] = x_[j];
        s_.termination_type = type;
        s_.termination = reason;
        s_.success = type == TerminationType::converged;
        s_.evaluations = s_.residual_evaluations + s_.jacobian_evaluations;
    }
    // The current point's cost and Jacobian become the result's.
    void keep_current_point() {
        s_.best_cost = 2.0 * f_;
        s_.jacobian_at_best = std::move(J_);
    }
    // A history row; false when the progress callback says stop.
    bool record(int iteration) {
        s_.history.push_back(HistoryRow{iteration, s_.residual_evaluations + s_.jacobian_evaluations, 2.0 * f_});
        return !progress_ || progress_(s_.history.back());
    }

    // Residuals and Jacobian at the start, and history row 0. False when the run ends there.
    bool iteration_zero() {
        const double inf = std::numeric_limits<double>::infinity();
        ++s_.jacobian_evaluations;
        if (!evaluate_jacobian(problem_, x_, r_, J_)) {
            s_.best_cost = s_.initial_cost = inf;
            if (problem_.stopped()) {
                finish(TerminationType::stopped, "stopped");
                return false;
            }
            ++s_.failed_evaluations;
            s_.history.push_back(HistoryRow{0, s_.jacobian_evaluations, inf});
            const std::string why = problem_.failure(x_.data());
            finish(TerminationType::start_failed, why.empty() ? std::string("start failed") : "start failed: " + why);
            return false;
        }
        f_ = 0.5 * r_.squaredNorm();  // the solver's cost ½‖r‖²; reported as Σr² = 2f
        s_.initial_cost = 2.0 * f_;
        if (!record(0)) {
            finish(TerminationType::stopped, "stopped");
            keep_current_point();
            return false;
        }
        return true;
    }

    // One iteration; false when the run ends.
    bool iteration() {
        if (fresh_jacobian_) {
            fresh_jacobian_ = false;
            if (!set_up_jacobian()) return false;
        }
        if (s_.iterations >= settings_.max_iterations) {
            finish(TerminationType::iteration_limit, "iteration limit");
            return false;
        }
        ++s_.iterations;

        const TrialStep trial = compute_trial_step(lambda_, x_trial_, step_);
        TrialPoint point = evaluate_trial_point(trial);
        if (point.halted) {  // drop this trial, stop at the last accepted point
            --s_.iterations;
            finish(TerminationType::stopped, "stopped");
            return false;
        }
        const double f_before = f_;
        const double actual = f_ - point.f;
        const double rho = point.evaluable && trial.predicted > 0 ? actual / trial.predicted
                                                                  : -std::numeric_limits<double>::infinity();  // gain ratio
        bool accepted = rho > kAcceptRatio;
        if (accepted) {
            switch (accept_trial_point()) {
                case Acceptance::accepted: break;
                case Acceptance::stopped:  // drop this trial, stop at the last accepted point
                    --s_.iterations;
                    finish(TerminationType::stopped, "stopped");
                    return false;
                case Acceptance::failed: accepted = point.evaluable = false; break;
            }
        }
        // Small only because the model fails a little further on (e.g. its simulation
        // diverges there): the cost is not stationary, the solver is stuck at that region.
        const bool blocked = failed_since_accept_;
        failed_since_accept_ = accepted ? false : (failed_since_accept_ || !point.evaluable);
        if (accepted) update_damping_on_success(rho);
        else update_damping_on_rejection();
        const bool go_on = record(s_.iterations);
        return !converged_or_ended(trial, point.evaluable, accepted, blocked, f_before, actual, go_on);
    }

    // A new Jacobian J at x: gradient, Moré's scaling, the active set, the gradient test,
    // J = Q R, and on the first one the initial damping. False when the gradient test ends the run.
    bool set_up_jacobian() {
        gradient_.noalias() = J_.transpose() * r_;  // ∇(½‖r‖²) = Jᵀr
        for (Index j = 0; j < m_; ++j) {
            column_norm_[j] = J_.col(j).norm();
            d_[j] = std::max(d_[j], column_norm_[j]);  // Moré's scaling: max over iterations
            scale_[j] = d_[j] > 0 ? d_[j] : 1.0;       // a parameter without effect keeps scale 1
        }
        // Active set: a parameter on a bound that the gradient pushes outward stays there.
        for (Index j = 0; j < m_; ++j)
            held_[static_cast<std::size_t>(j)] =
                lo_[j] == hi_[j] || (x_[j] <= lo_[j] && gradient_[j] > 0) || (x_[j] >= hi_[j] && gradient_[j] < 0);
        if (scaled_gradient_norm() <= settings_.gtol) {
            finish(TerminationType::converged, "gradient below gtol");
            return false;
        }
        factorize_jacobian();
        if (within_statistical_tolerance()) {
            finish(TerminationType::converged, "optimum within stol standard errors");
            return false;
        }
        if (first_jacobian_) {
            first_jacobian_ = false;
            lambda_ = initial_damping();
        }
        return true;
    }

    // Scaled gradient over the free parameters: the largest cosine between r and a column of J.
    double scaled_gradient_norm() const {
        const double r_norm = std::sqrt(2.0 * f_);
        double g_norm = 0.0;
        if (r_norm > 0)
            for (Index j = 0; j < m_; ++j)
                if (!held_[static_cast<std::size_t>(j)] && column_norm_[j] > 0)
                    g_norm = std::max(g_norm, std::abs(gradient_[j]) / (column_norm_[j] * r_norm));
        return g_norm;
    }

    // The statistical test (LmSettings::stol): ‖P r‖², r projected on the columns of J of the
    // free parameters, is the Gauss–Newton model's whole achievable decrease of Σr² (a held
    // parameter's column left out); below stol²·σ² with σ² = Σr²/(N − M_free), the linearised
    // optimum is within stol standard errors. With a rank-deficient J the projection spans
    // more than its columns: the test only errs towards going on.
    bool within_statistical_tolerance() const {
        if (!(settings_.stol > 0)) return false;
        const Index free = free_count();
        if (free == 0 || n_ <= free) return false;
        const double variance = 2.0 * f_ / static_cast<double>(n_ - free);
        return reducible_decrease() < settings_.stol * settings_.stol * variance;
    }

    Index free_count() const {
        Index free = 0;
        for (Index j = 0; j < m_; ++j)
            if (!held_[static_cast<std::size_t>(j)]) ++free;
        return free;
    }

    // ‖P r‖² at the last factorized Jacobian: the Gauss–Newton model's whole achievable
    // decrease of Σr² over the free parameters (a held parameter's column left out).
    double reducible_decrease() const { return free_count() == m_ ? qtr_.squaredNorm() : projected_decrease(J_, r_); }

    // ‖P r‖² for the Jacobian J and residuals r of one point, held columns left out.
    double projected_decrease(const Eigen::MatrixXd& J, const Eigen::VectorXd& r) const {
        Eigen::MatrixXd free_columns = J;
        for (Index j = 0; j < m_; ++j)
            if (held_[static_cast<std::size_t>(j)]) free_columns.col(j).setZero();
        const Eigen::HouseholderQR<Eigen::MatrixXd> qr(free_columns);
        Eigen::VectorXd qtr = r;
        qtr.applyOnTheLeft(qr.householderQ().adjoint());
        return qtr.head(std::min(n_, m_)).squaredNorm();
    }

    // J = Q R once per Jacobian; each trial then solves only an M-sized system.
    void factorize_jacobian() {
        qr_j_.compute(J_);
        const Index k = std::min(n_, m_);
        R_.setZero();
        for (Index c = 0; c < m_; ++c)
            for (Index i = 0; i <= std::min(c, k - 1); ++i) R_(i, c) = qr_j_.matrixQR()(i, c);
        qtr_full_ = r_;
        qtr_full_.applyOnTheLeft(qr_j_.householderQ().adjoint());
        qtr_.setZero();
        qtr_.head(k) = qtr_full_.head(k);
    }

    // λ0 = τ · the largest diagonal entry of the scaled JᵀJ.
    double initial_damping() const {
        double diagonal = 0.0;
        for (Index j = 0; j < m_; ++j) diagonal = std::max(diagonal, std::pow(column_norm_[j] / scale_[j], 2));
        return settings_.initial_damping * (diagonal > 0 ? diagonal : 1.0);
    }

    // The trial point for damping λ, feasible:
    //  1. a parameter on a bound whose step points outward joins the held set (p_j = 0), and
    //     the step is solved again;
    //  2. a free parameter whose step would cross a bound is put on it (p_j = its distance
    //     to the bound, δ_j), and the step of the others is solved again for that
    //     displacement: min ‖R p + Qᵀr‖² + λ‖D p‖² with p_j = δ_j, i.e. with Qᵀr + R δ
    //     on the right and those columns held. The step cut off at the bound instead keeps
    //     the others' values that compensated for the part cut off: with correlated
    //     parameters it can predict an increase, and LM then rejects it and raises λ until
    //     the step stays inside.
    // Each repeats while the set grows (at most M times each).
    TrialStep compute_trial_step(double damping, Eigen::VectorXd& point, Eigen::VectorXd& taken) {
        hold_outward_parameters(damping);
        put_crossing_parameters_on_bounds(damping);
        TrialStep t;
        for (Index j = 0; j < m_; ++j) {
            point[j] = std::clamp(x_[j] + p_[j], lo_[j], hi_[j]);
            taken[j] = point[j] - x_[j];
            if (taken[j] != 0) t.moves = true;
        }
        t.finite = taken.allFinite();
        // (The clamp above only catches rounding of x + δ_j.) For the step s taken:
        // ½‖r‖² − ½‖r + J s‖² = −(Qᵀr)ᵀ(R s) − ½‖R s‖².
        if (t.finite) {
            Rs_.noalias() = R_.triangularView<Eigen::Upper>() * taken;
            t.predicted = -qtr_.dot(Rs_) - 0.5 * Rs_.squaredNorm();
        }
        return t;
    }

    // Step 1 of compute_trial_step: p for the held set grown by the parameters on a bound
    // whose step points outward.
    void hold_outward_parameters(double damping) {
        held_trial_ = held_;
        for (Index pass = 0; pass <= m_; ++pass) {
            damped_.solve(R_, qtr_, scale_, damping, held_trial_, p_);
            bool changed = false;
            for (Index j = 0; j < m_; ++j) {
                auto& h = held_trial_[static_cast<std::size_t>(j)];
                if (!h && ((x_[j] <= lo_[j] && p_[j] < 0) || (x_[j] >= hi_[j] && p_[j] > 0))) {
                    h = 1;
                    changed = true;
                }
            }
            if (!changed) break;
        }
    }

    // Step 2 of compute_trial_step: the parameters whose step would cross a bound put on it,
    // and p of the others solved again for that displacement.
    void put_crossing_parameters_on_bounds(double damping) {
        on_bound_ = held_trial_;
        to_bound_.setZero();
        for (Index pass = 0; pass <= m_; ++pass) {
            bool changed = false;
            for (Index j = 0; j < m_; ++j) {
                auto& b = on_bound_[static_cast<std::size_t>(j)];
                if (b || !(x_[j] + p_[j] < lo_[j] || x_[j] + p_[j] > hi_[j])) continue;
                to_bound_[j] = (x_[j] + p_[j] < lo_[j] ? lo_[j] : hi_[j]) - x_[j];
                b = 1;
                changed = true;
            }
            if (!changed) break;
            qtr_on_bound_.noalias() = R_.triangularView<Eigen::Upper>() * to_bound_;
            qtr_on_bound_ += qtr_;
            damped_.solve(R_, qtr_on_bound_, scale_, damping, on_bound_, p_);
            p_ += to_bound_;  // held: 0 + 0; put on a bound: 0 + δ_j
        }
    }

    // The residuals at x_trial (from the trials evaluated ahead when it is one of them) and
    // its cost. A trial that does not move, or is not finite, is not evaluated.
    TrialPoint evaluate_trial_point(const TrialStep& trial) {
        TrialPoint point;
        point.evaluable = trial.finite;
        point.f = f_;
        if (!(trial.finite && trial.moves)) return point;
        ++s_.residual_evaluations;
        if (const AheadTrial* known = find_ahead(x_trial_)) {  // evaluated next to an earlier rejected step
            ++s_.taken_ahead;
            r_trial_ = known->r;
            point.evaluable = known->ok;
        } else {
            evaluate_with_ahead(trial_count_left());
            point.evaluable = side_ok_[0] != 0;
            point.halted = side_stopped_[0] != 0;
        }
        if (!point.evaluable && point.halted) return point;
        point.halted = false;
        if (point.evaluable) point.evaluable = r_trial_.allFinite();
        if (point.evaluable) point.f = 0.5 * r_trial_.squaredNorm();
        point.evaluable = point.evaluable && std::isfinite(point.f);
        if (!point.evaluable) ++s_.failed_evaluations;
        return point;
    }

    // The gain ratio was good: the Jacobian at the trial point, which becomes the current one.
    Acceptance accept_trial_point() {
        ahead_count_ = 0;  // the trials ahead were for this Jacobian's steps
        ++s_.jacobian_evaluations;
        if (evaluate_jacobian(problem_, x_trial_, r_trial_, J_trial_)) {
            x_ = x_trial_;
            r_.swap(r_trial_);
            J_.swap(J_trial_);
            f_ = 0.5 * r_.squaredNorm();
            fresh_jacobian_ = true;
            return Acceptance::accepted;
        }
        if (problem_.stopped()) return Acceptance::stopped;
        ++s_.failed_evaluations;  // the model ran but its Jacobian did not: a failed step
        return Acceptance::failed;
    }

    // Nielsen's damping update (Madsen, Nielsen & Tingleff 2004, eq. 2.21).
    void update_damping_on_success(double rho) {
        lambda_ *= std::max(1.0 / 3.0, 1.0 - std::pow(2.0 * rho - 1.0, 3));
        lambda_ = std::max(lambda_, kMinDamping);
        nu_ = 2.0;
        rejected_in_row_ = 0;
    }
    void update_damping_on_rejection() {
        lambda_ *= nu_;
        nu_ *= 2.0;
        ++rejected_in_row_;
    }

    // The convergence tests after an iteration, then the stop request and the rejection
    // limit; true (and the run finished) when one of them ends the run.
    bool converged_or_ended(const TrialStep& trial, bool evaluable, bool accepted, bool blocked, double f_before,
                            double actual, bool go_on) {
        const double step_norm = scale_.cwiseProduct(step_).norm();
        const double x_norm = scale_.cwiseProduct(x_).norm();
        const bool small_step = trial.finite && step_norm <= settings_.xtol * (x_norm + settings_.xtol);
        if (accepted && f_before > 0 && std::abs(actual) <= settings_.ftol * f_before &&
            trial.predicted <= settings_.ftol * f_before) {
            finish(TerminationType::converged, "cost change below ftol");
            return true;
        }
        // A step that cannot be evaluated says nothing about convergence; a tiny evaluable
        // step means the iterates have settled, or that no smaller one lowers the cost
        // (MINPACK's xtol test), unless failed evaluations forced it to be that small.
        // The statistical cost test (stol): accepted steps that lower Σr² by less than
        // stol²·σ² (σ² = Σr²/(N − M)), as measured and as predicted, twice in a row: the
        // cost has settled far below what the noise lets the data tell apart (the noise's
        // own spread of Σr² is about σ²·√(2N)). On weakly determined problems LM otherwise
        // crawls along a flat valley to its iteration limit.
        // Not when failed evaluations since the last accepted step kept the step small:
        // the cost is not stationary there (as for xtol below).
        // Nor far from a minimum: there Σr²/(N − M) is the model's misfit, not the noise, and
        // small steps mean a narrow valley, not a flat one. The steps count only while the
        // Gauss–Newton model at the accepted point promises at most kSettledReducible·σ² more
        // (its linearised optimum within 5 standard errors); a poor start otherwise
        // "converged" thousands of times above the optimum.
        if (!evaluable || blocked) settled_steps_ = 0;
        if (accepted && !blocked && settings_.stol > 0 && n_ > m_) {
            const double noise = settings_.stol * settings_.stol * 2.0 * f_before / static_cast<double>(n_ - m_);
            // At the accepted point, whose Jacobian and residuals are now J_ and r_.
            const bool settled = 2.0 * std::abs(actual) <= noise && 2.0 * trial.predicted <= noise &&
                                 projected_decrease(J_, r_) <= kSettledReducible * 2.0 * f_ / static_cast<double>(n_ - m_);
            settled_steps_ = settled ? settled_steps_ + 1 : 0;
            if (settled_steps_ >= 2) {
                finish(TerminationType::converged, "cost change below the noise (stol)");
                return true;
            }
        }
        if (evaluable && small_step) {
            if (blocked) finish(TerminationType::no_progress, "no progress");
            else finish(TerminationType::converged, "step below xtol");
            return true;
        }
        if (!go_on) {
            finish(TerminationType::stopped, "stopped");
            return true;
        }
        if (!accepted && (rejected_in_row_ >= settings_.max_consecutive_rejections || !std::isfinite(lambda_))) {
            finish(TerminationType::no_progress, "no progress");
            return true;
        }
        return false;
    }

    // Trials evaluated ahead: with the Jacobian unchanged, a rejection only raises λ (to λν,
    // then ·2ν, ...), so the next trial points are known before the current one is judged.
    // They are evaluated side by side with it; a later iteration takes its residuals
    // from here when its trial point is the same to the bit.
    void set_up_trials_ahead() {
        concurrency_ = static_cast<std::size_t>(std::clamp(problem_.max_concurrent_residuals(), 1, kMaxTrialsSideBySide));
        ahead_.assign(concurrency_ - 1, AheadTrial{Eigen::VectorXd(m_), Eigen::VectorXd(n_), false});
        side_x_.resize(concurrency_);
        side_r_.resize(concurrency_);
        side_ok_.resize(concurrency_);
        side_stopped_.resize(concurrency_);
    }

    const AheadTrial* find_ahead(const Eigen::VectorXd& point) const {
        for (std::size_t k = 0; k < ahead_count_; ++k)
            if (ahead_[k].x == point) return &ahead_[k];
        return nullptr;
    }

    // The steps LM may still take before the Jacobian changes, the current one included.
    std::size_t trial_count_left() const {
        const int by_limit = std::min(settings_.max_iterations - s_.iterations + 1,
                                      settings_.max_consecutive_rejections - rejected_in_row_);
        return static_cast<std::size_t>(std::max(1, by_limit));
    }

    // x_trial into r_trial (side_ok[0], side_stopped[0]) and, beside it, the trials of the
    // next rejections that move and are finite, into `ahead`.
    void evaluate_with_ahead(std::size_t steps_left) {
        std::size_t count = 1;
        side_x_[0] = x_trial_.data();
        side_r_[0] = r_trial_.data();
        double damping = lambda_, growth = nu_;
        // As many as the problem evaluates at once now (at most the arrays' concurrency_).
        const auto now = static_cast<std::size_t>(std::max(1, problem_.concurrent_residuals()));
        const std::size_t wanted = std::min({now, concurrency_, steps_left});
        while (count < wanted) {
            damping *= growth;  // as a rejection updates λ and ν
            growth *= 2.0;
            if (!std::isfinite(damping)) break;
            AheadTrial& a = ahead_[count - 1];
            const TrialStep t = compute_trial_step(damping, a.x, ahead_step_);
            if (!t.finite || !t.moves) break;  // that iteration evaluates nothing
            side_x_[count] = a.x.data();
            side_r_[count] = a.r.data();
            ++count;
        }
        problem_.residuals_side_by_side(count, side_x_.data(), side_r_.data(), side_ok_.data(), side_stopped_.data());
        ahead_count_ = 0;
        for (std::size_t k = 1; k < count && !side_stopped_[k]; ++k) {
            ahead_[k - 1].ok = side_ok_[k] != 0;
            ahead_count_ = k;
        }
        s_.evaluated_ahead += static_cast<long long>(count - 1);
    }

    const LmSettings& settings_;
    LeastSquaresProblem& problem_;
    const LmProgress& progress_;
    const Index m_, n_;
    LmSummary s_;

    // The iterate, the trial point, their residuals and Jacobians.
    Eigen::VectorXd lo_, hi_, x_, x_trial_;
    Eigen::VectorXd r_, r_trial_, qtr_full_;
    Eigen::MatrixXd J_, J_trial_;
    double f_ = 0.0;  // ½‖r‖² at x
    // The current Jacobian's set-up and the trial step's work space.
    Eigen::VectorXd gradient_, column_norm_, d_, scale_;
    Eigen::VectorXd p_, step_, qtr_, Rs_;
    Eigen::MatrixXd R_;
    Eigen::HouseholderQR<Eigen::MatrixXd> qr_j_;
    DampedStep damped_;
    std::vector<char> held_, held_trial_, on_bound_;
    Eigen::VectorXd to_bound_, qtr_on_bound_;
    // The damping and the iteration state.
    double lambda_ = 0.0, nu_ = 2.0;
    int rejected_in_row_ = 0;
    bool first_jacobian_ = true, fresh_jacobian_ = true;
    int settled_steps_ = 0;        // accepted steps in a row that met the statistical cost test
    bool failed_since_accept_ = false;  // a trial since the last accepted step could not be evaluated
    // The trials evaluated ahead and the buffers of a side-by-side evaluation.
    std::size_t concurrency_ = 1;
    std::vector<AheadTrial> ahead_;
    std::size_t ahead_count_ = 0;
    Eigen::VectorXd ahead_step_;
    std::vector<const double*> side_x_;
    std::vector<double*> side_r_;
    std::vector<char> side_ok_, side_stopped_;
};

}  // namespace

LmSummary run_levenberg_marquardt(const LmSettings& settings, std::vector<double> x0,
                                  const std::vector<double>& lower, const std::vector<double>& upper,
                                  LeastSquaresProblem& problem, const LmProgress& progress) {
    check_arguments(settings, x0, lower, upper, problem.residual_count());
    return LevenbergMarquardt(settings, x0, lower, upper, problem, progress).minimize();
}

void to_parameters(const ParameterScaling& scaling, LmSummary& s) {
    scaling.best_to_parameters(s);
    if (s.best.size() == scaling.dimension() && s.jacobian_at_best.cols() == static_cast<Eigen::Index>(scaling.dimension()))
        scaling.jacobian_to_parameters(s.best.data(), s.jacobian_at_best);
}

}  // namespace tvid

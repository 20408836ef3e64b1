#include "tvid/optim/levenberg_marquardt.hpp"

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
    if (!(settings.ftol >= 0) || !(settings.xtol >= 0) || !(settings.gtol >= 0))
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

}  // namespace

LmSummary run_levenberg_marquardt(const LmSettings& settings, std::vector<double> x0,
                                  const std::vector<double>& lower, const std::vector<double>& upper,
                                  LeastSquaresProblem& problem, const LmProgress& progress) {
    const std::size_t residual_count = problem.residual_count();
    check_arguments(settings, x0, lower, upper, residual_count);
    const auto m = static_cast<Index>(x0.size());
    const auto n = static_cast<Index>(residual_count);
    const auto mu = x0.size();
    const double inf = std::numeric_limits<double>::infinity();

    // Everything the iterations touch is allocated here, once.
    Eigen::VectorXd lo(m), hi(m), x(m), x_trial(m);
    for (Index j = 0; j < m; ++j) {
        const auto u = static_cast<std::size_t>(j);
        lo[j] = lower[u];
        hi[j] = upper[u];
        x[j] = std::clamp(x0[u], lo[j], hi[j]);  // start feasible
    }
    Eigen::VectorXd r(n), r_trial(n), qtr_full(n);
    Eigen::MatrixXd J(n, m), J_trial(n, m);
    Eigen::VectorXd gradient(m), column_norm(m), d = Eigen::VectorXd::Zero(m), scale(m);
    Eigen::VectorXd p(m), step(m), qtr(m), Rs(m);
    Eigen::MatrixXd R = Eigen::MatrixXd::Zero(m, m);
    Eigen::HouseholderQR<Eigen::MatrixXd> qr_j(n, m);
    DampedStep damped(m);
    std::vector<char> held(mu, 0), held_trial(mu, 0), on_bound(mu, 0);
    Eigen::VectorXd to_bound(m), qtr_on_bound(m);

    LmSummary s;
    s.best.assign(mu, 0.0);
    s.history.reserve(static_cast<std::size_t>(std::min(settings.max_iterations, 1 << 16)) + 1);
    auto finish = [&](const char* reason, bool converged) {
        for (Index j = 0; j < m; ++j) s.best[static_cast<std::size_t>(j)] = x[j];
        s.termination = reason;
        s.success = converged;
    };

    ++s.jacobian_evaluations;
    if (!evaluate_jacobian(problem, x, r, J)) {
        s.best_cost = s.initial_cost = inf;
        if (problem.stopped()) {
            finish("stopped", false);
            return s;
        }
        ++s.failed_evaluations;
        s.history.push_back(HistoryRow{0, s.jacobian_evaluations, inf});
        finish("start failed", false);
        return s;
    }
    double f = 0.5 * r.squaredNorm();  // the solver's cost ½‖r‖²; reported as Σr² = 2f
    s.initial_cost = 2.0 * f;
    auto record = [&](int iteration) {
        s.history.push_back(HistoryRow{iteration, s.residual_evaluations + s.jacobian_evaluations, 2.0 * f});
        return !progress || progress(s.history.back());
    };
    if (!record(0)) {
        finish("stopped", false);
        s.best_cost = 2.0 * f;
        s.jacobian_at_best = std::move(J);
        return s;
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
    struct TrialStep {
        bool finite = false, moves = false;
        double predicted = 0.0;  // the reduction of ½‖r‖² that the linear model predicts
    };
    auto make_trial = [&](double damping, Eigen::VectorXd& point, Eigen::VectorXd& taken) {
        held_trial = held;
        for (Index pass = 0; pass <= m; ++pass) {
            damped.solve(R, qtr, scale, damping, held_trial, p);
            bool changed = false;
            for (Index j = 0; j < m; ++j) {
                auto& h = held_trial[static_cast<std::size_t>(j)];
                if (!h && ((x[j] <= lo[j] && p[j] < 0) || (x[j] >= hi[j] && p[j] > 0))) {
                    h = 1;
                    changed = true;
                }
            }
            if (!changed) break;
        }
        on_bound = held_trial;
        to_bound.setZero();
        for (Index pass = 0; pass <= m; ++pass) {
            bool changed = false;
            for (Index j = 0; j < m; ++j) {
                auto& b = on_bound[static_cast<std::size_t>(j)];
                if (b || !(x[j] + p[j] < lo[j] || x[j] + p[j] > hi[j])) continue;
                to_bound[j] = (x[j] + p[j] < lo[j] ? lo[j] : hi[j]) - x[j];
                b = 1;
                changed = true;
            }
            if (!changed) break;
            qtr_on_bound.noalias() = R.triangularView<Eigen::Upper>() * to_bound;
            qtr_on_bound += qtr;
            damped.solve(R, qtr_on_bound, scale, damping, on_bound, p);
            p += to_bound;  // held: 0 + 0; put on a bound: 0 + δ_j
        }
        TrialStep t;
        for (Index j = 0; j < m; ++j) {
            point[j] = std::clamp(x[j] + p[j], lo[j], hi[j]);
            taken[j] = point[j] - x[j];
            if (taken[j] != 0) t.moves = true;
        }
        t.finite = taken.allFinite();
        // (The clamp above only catches rounding of x + δ_j.) For the step s taken:
        // ½‖r‖² − ½‖r + J s‖² = −(Qᵀr)ᵀ(R s) − ½‖R s‖².
        if (t.finite) {
            Rs.noalias() = R.triangularView<Eigen::Upper>() * taken;
            t.predicted = -qtr.dot(Rs) - 0.5 * Rs.squaredNorm();
        }
        return t;
    };

    // Trials evaluated ahead: with the Jacobian unchanged, a rejection only raises λ (to λν,
    // then ·2ν, ...), so the next trial points are known before the current one is judged.
    // They are evaluated side by side with it; a later iteration takes its residuals
    // from here when its trial point is the same to the bit.
    struct AheadTrial {
        Eigen::VectorXd x, r;
        bool ok = false;
    };
    const auto concurrency =
        static_cast<std::size_t>(std::clamp(problem.concurrent_residuals(), 1, kMaxTrialsSideBySide));
    std::vector<AheadTrial> ahead(concurrency - 1, AheadTrial{Eigen::VectorXd(m), Eigen::VectorXd(n), false});
    std::size_t ahead_count = 0;
    Eigen::VectorXd ahead_step(m);
    std::vector<const double*> side_x(concurrency);
    std::vector<double*> side_r(concurrency);
    std::vector<char> side_ok(concurrency), side_stopped(concurrency);
    auto find_ahead = [&](const Eigen::VectorXd& point) -> const AheadTrial* {
        for (std::size_t k = 0; k < ahead_count; ++k)
            if (ahead[k].x == point) return &ahead[k];
        return nullptr;
    };
    double lambda = 0.0, nu = 2.0;
    int rejected_in_row = 0;
    // The steps LM may still take before the Jacobian changes, the current one included.
    auto trial_count_left = [&]() {
        const int by_limit = std::min(settings.max_iterations - s.iterations + 1,
                                      settings.max_consecutive_rejections - rejected_in_row);
        return static_cast<std::size_t>(std::max(1, by_limit));
    };
    // x_trial into r_trial (side_ok[0], side_stopped[0]) and, beside it, the trials of the
    // next rejections that move and are finite, into `ahead`.
    auto evaluate_with_ahead = [&](std::size_t steps_left) {
        std::size_t count = 1;
        side_x[0] = x_trial.data();
        side_r[0] = r_trial.data();
        double damping = lambda, growth = nu;
        const std::size_t wanted = std::min(concurrency, steps_left);
        while (count < wanted) {
            damping *= growth;  // as a rejection updates λ and ν below
            growth *= 2.0;
            if (!std::isfinite(damping)) break;
            AheadTrial& a = ahead[count - 1];
            const TrialStep t = make_trial(damping, a.x, ahead_step);
            if (!t.finite || !t.moves) break;  // that iteration evaluates nothing
            side_x[count] = a.x.data();
            side_r[count] = a.r.data();
            ++count;
        }
        problem.residuals_side_by_side(count, side_x.data(), side_r.data(), side_ok.data(), side_stopped.data());
        ahead_count = 0;
        for (std::size_t k = 1; k < count && !side_stopped[k]; ++k) {
            ahead[k - 1].ok = side_ok[k] != 0;
            ahead_count = k;
        }
        s.evaluated_ahead += static_cast<long long>(count - 1);
    };
    bool first = true, fresh_jacobian = true;
    bool failed_since_accept = false;  // a trial since the last accepted step could not be evaluated
    for (;;) {
        if (fresh_jacobian) {
            fresh_jacobian = false;
            gradient.noalias() = J.transpose() * r;  // ∇(½‖r‖²) = Jᵀr
            for (Index j = 0; j < m; ++j) {
                column_norm[j] = J.col(j).norm();
                d[j] = std::max(d[j], column_norm[j]);  // Moré's scaling: max over iterations
                scale[j] = d[j] > 0 ? d[j] : 1.0;       // a parameter without effect keeps scale 1
            }
            // Active set: a parameter on a bound that the gradient pushes outward stays there.
            for (Index j = 0; j < m; ++j)
                held[static_cast<std::size_t>(j)] =
                    lo[j] == hi[j] || (x[j] <= lo[j] && gradient[j] > 0) || (x[j] >= hi[j] && gradient[j] < 0);
            // Scaled gradient over the free parameters: cosine between r and each column of J.
            const double r_norm = std::sqrt(2.0 * f);
            double g_norm = 0.0;
            if (r_norm > 0)
                for (Index j = 0; j < m; ++j)
                    if (!held[static_cast<std::size_t>(j)] && column_norm[j] > 0)
                        g_norm = std::max(g_norm, std::abs(gradient[j]) / (column_norm[j] * r_norm));
            if (g_norm <= settings.gtol) {
                finish("gradient below gtol", true);
                break;
            }
            // J = Q R once per Jacobian; each trial then solves only an M-sized system.
            qr_j.compute(J);
            const Index k = std::min(n, m);
            R.setZero();
            for (Index c = 0; c < m; ++c)
                for (Index i = 0; i <= std::min(c, k - 1); ++i) R(i, c) = qr_j.matrixQR()(i, c);
            qtr_full = r;
            qtr_full.applyOnTheLeft(qr_j.householderQ().adjoint());
            qtr.setZero();
            qtr.head(k) = qtr_full.head(k);
            if (first) {
                first = false;
                double diagonal = 0.0;  // largest diagonal entry of the scaled JᵀJ
                for (Index j = 0; j < m; ++j) diagonal = std::max(diagonal, std::pow(column_norm[j] / scale[j], 2));
                lambda = settings.initial_damping * (diagonal > 0 ? diagonal : 1.0);
            }
        }
        if (s.iterations >= settings.max_iterations) {
            finish("iteration limit", false);
            break;
        }
        ++s.iterations;

        const TrialStep trial = make_trial(lambda, x_trial, step);
        bool evaluable = trial.finite;
        double f_trial = f;
        if (trial.finite && trial.moves) {
            ++s.residual_evaluations;
            bool halted = false;
            if (const AheadTrial* known = find_ahead(x_trial)) {  // evaluated next to an earlier rejected step
                ++s.taken_ahead;
                r_trial = known->r;
                evaluable = known->ok;
            } else {
                evaluate_with_ahead(trial_count_left());
                evaluable = side_ok[0] != 0;
                halted = side_stopped[0] != 0;
            }
            if (!evaluable && halted) {  // drop this trial, stop at the last accepted point
                --s.iterations;
                finish("stopped", false);
                break;
            }
            if (evaluable) evaluable = r_trial.allFinite();
            if (evaluable) f_trial = 0.5 * r_trial.squaredNorm();
            evaluable = evaluable && std::isfinite(f_trial);
            if (!evaluable) ++s.failed_evaluations;
        }
        const double predicted = trial.predicted;
        const double f_before = f;
        const double actual = f - f_trial;
        const double rho = evaluable && predicted > 0 ? actual / predicted : -inf;  // gain ratio
        bool accepted = rho > kAcceptRatio;
        if (accepted) {
            ahead_count = 0;  // the trials ahead were for this Jacobian's steps
            ++s.jacobian_evaluations;
            if (evaluate_jacobian(problem, x_trial, r_trial, J_trial)) {
                x = x_trial;
                r.swap(r_trial);
                J.swap(J_trial);
                f = 0.5 * r.squaredNorm();
                fresh_jacobian = true;
            } else if (problem.stopped()) {  // drop this trial, stop at the last accepted point
                --s.iterations;
                finish("stopped", false);
                break;
            } else {  // the model ran but its Jacobian did not: a failed step
                ++s.failed_evaluations;
                accepted = evaluable = false;
            }
        }
        // Small only because the model fails a little further on (e.g. its simulation
        // diverges there): the cost is not stationary, the solver is stuck at that region.
        const bool blocked = failed_since_accept;
        failed_since_accept = accepted ? false : (failed_since_accept || !evaluable);
        // Nielsen's damping update (Madsen, Nielsen & Tingleff 2004, eq. 2.21).
        if (accepted) {
            lambda *= std::max(1.0 / 3.0, 1.0 - std::pow(2.0 * rho - 1.0, 3));
            lambda = std::max(lambda, kMinDamping);
            nu = 2.0;
            rejected_in_row = 0;
        } else {
            lambda *= nu;
            nu *= 2.0;
            ++rejected_in_row;
        }
        const bool go_on = record(s.iterations);

        const double step_norm = scale.cwiseProduct(step).norm();
        const double x_norm = scale.cwiseProduct(x).norm();
        const bool small_step = trial.finite && step_norm <= settings.xtol * (x_norm + settings.xtol);
        if (accepted && f_before > 0 && std::abs(actual) <= settings.ftol * f_before &&
            predicted <= settings.ftol * f_before) {
            finish("cost change below ftol", true);
            break;
        }
        // A step that cannot be evaluated says nothing about convergence; a tiny evaluable
        // step means the iterates have settled, or that no smaller one lowers the cost
        // (MINPACK's xtol test), unless failed evaluations forced it to be that small.
        if (evaluable && small_step) {
            if (blocked) finish("no progress", false);
            else finish("step below xtol", true);
            break;
        }
        if (!go_on) {
            finish("stopped", false);
            break;
        }
        if (!accepted && (rejected_in_row >= settings.max_consecutive_rejections || !std::isfinite(lambda))) {
            finish("no progress", false);
            break;
        }
    }
    s.best_cost = 2.0 * f;
    s.jacobian_at_best = std::move(J);
    return s;
}

}  // namespace tvid

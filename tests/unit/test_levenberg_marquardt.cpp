// Levenberg–Marquardt with bounds on least-squares problems with a known answer. Every
// problem here has an analytic Jacobian (checked once against central differences).
#include <catch2/catch.hpp>
#include <Eigen/QR>
#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include "tvid/optim/levenberg_marquardt.hpp"

namespace TVID_UNITY_ID {  // unique to this file in a unity build (tests/CMakeLists.txt)

using namespace tvid;

namespace {

constexpr double kNone = 1e300;  // "no bound"

std::vector<double> unbounded_lower(std::size_t m) { return std::vector<double>(m, -kNone); }
std::vector<double> unbounded_upper(std::size_t m) { return std::vector<double>(m, kNone); }

bool non_increasing(const std::vector<HistoryRow>& history) {
    for (std::size_t k = 1; k < history.size(); ++k)
        if (history[k].best_cost > history[k - 1].best_cost || history[k].iteration != static_cast<int>(k) ||
            history[k].evaluations < history[k - 1].evaluations)
            return false;
    return !history.empty() && history.front().iteration == 0;
}

// Rosenbrock's valley as residuals: r = (10 (x2 − x1²), 1 − x1), minimum 0 at (1, 1).
struct Rosenbrock : LeastSquaresProblem {
    std::size_t residual_count() const override { return 2; }
    bool residuals(const double* x, double* r) override {
        r[0] = 10.0 * (x[1] - x[0] * x[0]);
        r[1] = 1.0 - x[0];
        return true;
    }
    bool jacobian(const double* x, double* r, Eigen::MatrixXd& J) override {
        residuals(x, r);
        J(0, 0) = -20.0 * x[0];
        J(0, 1) = 10.0;
        J(1, 0) = -1.0;
        J(1, 1) = 0.0;
        return true;
    }
};

// y = a exp(−b t) + c sampled on t = 0, 0.1, …, 3.9 from exact (a, b, c) = (2, 1.3, 0.5).
struct ExponentialDecay : LeastSquaresProblem {
    static constexpr std::array<double, 3> truth{2.0, 1.3, 0.5};
    std::vector<double> t, y;
    ExponentialDecay() {
        for (int i = 0; i < 40; ++i) {
            t.push_back(0.1 * i);
            y.push_back(truth[0] * std::exp(-truth[1] * t.back()) + truth[2]);
        }
    }
    std::size_t residual_count() const override { return t.size(); }
    bool residuals(const double* x, double* r) override {
        for (std::size_t i = 0; i < t.size(); ++i) r[i] = x[0] * std::exp(-x[1] * t[i]) + x[2] - y[i];
        return true;
    }
    bool jacobian(const double* x, double* r, Eigen::MatrixXd& J) override {
        for (std::size_t i = 0; i < t.size(); ++i) {
            const auto row = static_cast<Eigen::Index>(i);
            const double e = std::exp(-x[1] * t[i]);
            r[i] = x[0] * e + x[2] - y[i];
            J(row, 0) = e;
            J(row, 1) = -x[0] * t[i] * e;
            J(row, 2) = 1.0;
        }
        return true;
    }
};

// The exponential fit whose "simulation" fails in part of the space, as a model with too
// small a decay rate might diverge: residuals() returns false for b < fail_below and NaN
// values for b < nan_below. From (1, 1.95, 0.25) the first free steps go to b ≈ 0.2–0.37.
struct FailingDecay : ExponentialDecay {
    double fail_below = 0.3, nan_below = 0.7;
    long long failures = 0;
    bool residuals(const double* x, double* r) override {
        if (x[1] < fail_below) {
            ++failures;
            return false;
        }
        ExponentialDecay::residuals(x, r);
        if (x[1] < nan_below) {
            ++failures;
            r[0] = std::numeric_limits<double>::quiet_NaN();
        }
        return true;
    }
    bool jacobian(const double* x, double* r, Eigen::MatrixXd& J) override {
        if (x[1] < nan_below) {
            ++failures;
            return false;
        }
        return ExponentialDecay::jacobian(x, r, J);
    }
};

// Impulse response of one inertia J on a spring-damper (c, k) to ground after an angular
// impulse H: θ(t) = H/(J ω_d) e^{−σt} sin(ω_d t), σ = c/(2J), ω_d = √(k/J − σ²). With
// J = 1e-3 kg m², c = 10 N m s/rad, k = 1e5 N m/rad the parameters span eight decades.
// The solver sees x_j = p_j / unit_j: unit = 1 gives the badly scaled problem, unit = the
// magnitudes its well-scaled twin; the residuals are the same function either way.
struct TorsionalImpulse : LeastSquaresProblem {
    static constexpr std::array<double, 3> truth{1e-3, 10.0, 1e5};
    static constexpr double H = 1e-2;
    std::array<double, 3> unit;
    std::vector<double> t, y;
    explicit TorsionalImpulse(std::array<double, 3> units) : unit(units) {
        for (int i = 0; i < 150; ++i) t.push_back(1e-5 * i);  // 1.5 ms, about two periods
        y.assign(t.size(), 0.0);
        std::vector<double> r(t.size());
        const std::array<double, 3> x{truth[0] / unit[0], truth[1] / unit[1], truth[2] / unit[2]};
        residuals(x.data(), r.data());
        for (std::size_t i = 0; i < t.size(); ++i) y[i] = r[i];  // y was 0, so r = θ(t; truth)
    }
    std::size_t residual_count() const override { return t.size(); }
    bool evaluate(const double* x, double* r, Eigen::MatrixXd* Jac) const {
        const double J = x[0] * unit[0], c = x[1] * unit[1], k = x[2] * unit[2];
        const double sigma = c / (2 * J), omega2 = k / J - sigma * sigma;
        if (!(J > 0) || !(omega2 > 0)) return false;  // not an underdamped oscillator
        const double wd = std::sqrt(omega2), A = H / (J * wd);
        // Chain rule through (A, σ, ω_d).
        const std::array<double, 3> dsigma{-c / (2 * J * J), 1 / (2 * J), 0.0};
        const std::array<double, 3> domega2{-k / (J * J), 0.0, 1 / J};
        std::array<double, 3> dwd{}, dA{};
        for (std::size_t j = 0; j < 3; ++j) {
            dwd[j] = (domega2[j] - 2 * sigma * dsigma[j]) / (2 * wd);
            dA[j] = -H / (J * wd * wd) * dwd[j];
        }
        dA[0] += -H / (J * J * wd);
        for (std::size_t i = 0; i < t.size(); ++i) {
            const double e = std::exp(-sigma * t[i]), sn = std::sin(wd * t[i]), cs = std::cos(wd * t[i]);
            r[i] = A * e * sn - y[i];
            if (Jac)
                for (std::size_t j = 0; j < 3; ++j)
                    (*Jac)(static_cast<Eigen::Index>(i), static_cast<Eigen::Index>(j)) =
                        unit[j] * (dA[j] * e * sn - A * t[i] * e * sn * dsigma[j] + A * e * t[i] * cs * dwd[j]);
        }
        return true;
    }
    bool residuals(const double* x, double* r) override { return evaluate(x, r, nullptr); }
    bool jacobian(const double* x, double* r, Eigen::MatrixXd& J) override { return evaluate(x, r, &J); }
};

// r = (x1 − 3, 10 (x2 − x1²), 1 + 0.1 x2 + x3) on x1 ≤ 2, x3 ≥ 0. The unconstrained minimum
// (3, 9, −1.9) lies outside the box; the constrained one is x1 = 2, x3 = 0 (both gradients
// push outward there) and x2 minimizing 100 (x2 − 4)² + (1 + 0.1 x2)²: x2 = 799.8 / 200.02.
struct OptimumOnBound : LeastSquaresProblem {
    std::size_t residual_count() const override { return 3; }
    bool residuals(const double* x, double* r) override {
        r[0] = x[0] - 3.0;
        r[1] = 10.0 * (x[1] - x[0] * x[0]);
        r[2] = 1.0 + 0.1 * x[1] + x[2];
        return true;
    }
    bool jacobian(const double* x, double* r, Eigen::MatrixXd& J) override {
        residuals(x, r);
        J << 1.0, 0.0, 0.0,  //
            -20.0 * x[0], 10.0, 0.0,  //
            0.0, 0.1, 1.0;
        return true;
    }
};

// Linear residuals r = A x − b: one Gauss–Newton step from anywhere is the minimum.
struct LinearResiduals : LeastSquaresProblem {
    Eigen::MatrixXd A;
    Eigen::VectorXd b;
    std::size_t residual_count() const override { return static_cast<std::size_t>(A.rows()); }
    bool residuals(const double* x, double* r) override {
        Eigen::Map<Eigen::VectorXd>(r, A.rows()) = A * Eigen::Map<const Eigen::VectorXd>(x, A.cols()) - b;
        return true;
    }
    bool jacobian(const double* x, double* r, Eigen::MatrixXd& J) override {
        residuals(x, r);
        J = A;
        return true;
    }
    double cost(const Eigen::VectorXd& x) const { return (A * x - b).squaredNorm(); }
};

// Central differences of residuals(): only to check the analytic Jacobians above.
double jacobian_error(LeastSquaresProblem& problem, std::vector<double> x) {
    const auto n = problem.residual_count();
    const auto m = x.size();
    std::vector<double> r(n), rp(n), rm(n);
    Eigen::MatrixXd J(static_cast<Eigen::Index>(n), static_cast<Eigen::Index>(m));
    problem.jacobian(x.data(), r.data(), J);
    double worst = 0.0;
    for (std::size_t j = 0; j < m; ++j) {
        const double x0 = x[j], h = 1e-6 * std::max(std::abs(x0), 1e-3);
        x[j] = x0 + h;
        problem.residuals(x.data(), rp.data());
        x[j] = x0 - h;
        problem.residuals(x.data(), rm.data());
        x[j] = x0;
        const Eigen::Index c = static_cast<Eigen::Index>(j);
        const double norm = J.col(c).norm();
        for (std::size_t i = 0; i < n; ++i)
            worst = std::max(worst, std::abs((rp[i] - rm[i]) / (2 * h) - J(static_cast<Eigen::Index>(i), c)) / norm);
    }
    return worst;
}

}  // namespace

TEST_CASE("the test problems' analytic Jacobians agree with central differences", "[lm]") {
    Rosenbrock rosenbrock;
    ExponentialDecay decay;
    TorsionalImpulse bad({1.0, 1.0, 1.0}), twin({1e-3, 1.0, 1e5});
    OptimumOnBound bound;
    CHECK(jacobian_error(rosenbrock, {-1.2, 1.0}) < 1e-6);
    CHECK(jacobian_error(decay, {3.0, 0.65, 0.75}) < 1e-6);
    CHECK(jacobian_error(bad, {1.2e-3, 8.0, 0.9e5}) < 1e-6);
    CHECK(jacobian_error(twin, {1.2, 8.0, 0.9}) < 1e-6);
    CHECK(jacobian_error(bound, {0.5, 1.0, 2.0}) < 1e-6);
}

TEST_CASE("LM solves Rosenbrock's valley from (-1.2, 1)", "[lm]") {
    Rosenbrock problem;
    const auto s = run_levenberg_marquardt(LmSettings{}, {-1.2, 1.0}, unbounded_lower(2), unbounded_upper(2), problem);
    CAPTURE(s.termination, s.iterations, s.residual_evaluations, s.jacobian_evaluations);
    CHECK(s.success);
    CHECK(s.termination_type == TerminationType::converged);
    CHECK(s.best[0] == Approx(1.0).margin(1e-8));
    CHECK(s.best[1] == Approx(1.0).margin(1e-8));
    CHECK(s.best_cost < 1e-20);
    CHECK(s.initial_cost == Approx(24.2));  // Σr² = 4.4² + 2.2², not ½ of it
    CHECK(s.iterations < 40);
    CHECK(non_increasing(s.history));
    CHECK(s.history.size() == static_cast<std::size_t>(s.iterations) + 1);
    CHECK(s.history.back().evaluations == s.residual_evaluations + s.jacobian_evaluations);
    CHECK(s.jacobian_at_best.rows() == 2);
    CHECK(s.jacobian_at_best(0, 0) == Approx(-20.0 * s.best[0]));
}

// Rosenbrock's valley made steep and narrow, r = (a (x2 − x1²), 1 − x1), its two residuals among
// `rows` (the rest 0, as samples a candidate already fits): far from the minimum Σr²/(N − M)
// is the misfit, and LM's steps along the curved valley lower Σr² by less than a hundredth of it.
struct NarrowValley : LeastSquaresProblem {
    double a;
    std::size_t rows;
    NarrowValley(double steepness, std::size_t n) : a(steepness), rows(n) {}
    std::size_t residual_count() const override { return rows; }
    bool residuals(const double* x, double* r) override {
        std::fill(r, r + rows, 0.0);
        r[0] = a * (x[1] - x[0] * x[0]);
        r[1] = 1.0 - x[0];
        return true;
    }
    bool jacobian(const double* x, double* r, Eigen::MatrixXd& J) override {
        residuals(x, r);
        J.setZero();
        J(0, 0) = -2.0 * a * x[0];
        J(0, 1) = a;
        J(1, 0) = -1.0;
        return true;
    }
};

TEST_CASE("LM's noise-based stop holds near a minimum only: small steps along a narrow valley go on", "[lm]") {
    // With 100 rows the statistical cost test used to end this run after 5 iterations at
    // Σr² = 4.44 ("cost change below the noise (stol)"), where the minimum is 0 at (1, 1):
    // the Gauss–Newton model there still promised the whole misfit.
    NarrowValley problem(1e5, 100);
    LmSettings settings;
    settings.max_iterations = 10000;
    const auto s = run_levenberg_marquardt(settings, {-1.2, 1.0}, unbounded_lower(2), unbounded_upper(2), problem);
    CAPTURE(s.termination, s.iterations);
    CHECK(s.termination != "cost change below the noise (stol)");
    CHECK(s.success);
    CHECK(s.best_cost < 1e-12);
    CHECK(s.best[0] == Approx(1.0).margin(1e-6));
}

TEST_CASE("LM's statistical tolerance ends a noisy fit near its optimum, before the classical tolerances", "[lm]") {
    // The exponential decay with a deterministic ±0.01 "noise": stol ends it within a tenth of a
    // standard error of the optimum that stol 0 reaches, in fewer iterations.
    ExponentialDecay problem;
    for (std::size_t i = 0; i < problem.y.size(); ++i) problem.y[i] += 0.01 * std::sin(7.3 * static_cast<double>(i));
    const std::vector<double> start{1.5 * 2.0, 0.5 * 1.3, 1.5 * 0.5};
    LmSettings exact;
    exact.stol = 0.0;
    const auto optimum = run_levenberg_marquardt(exact, start, unbounded_lower(3), unbounded_upper(3), problem);
    const auto s = run_levenberg_marquardt(LmSettings{}, start, unbounded_lower(3), unbounded_upper(3), problem);
    CAPTURE(s.termination, s.iterations, optimum.termination, optimum.iterations);
    CHECK(s.success);
    CHECK(s.termination.find("stol") != std::string::npos);
    CHECK(s.iterations < optimum.iterations);
    // Σr² above the optimum's by at most stol² σ² (σ² = Σr²/(N − M)), twice that for the rounding.
    const double variance = optimum.best_cost / static_cast<double>(problem.t.size() - 3);
    CHECK(s.best_cost - optimum.best_cost <= 2 * 0.01 * variance);
}

TEST_CASE("LM recovers an exponential decay from a start 50 % off", "[lm]") {
    ExponentialDecay problem;
    const auto& truth = ExponentialDecay::truth;
    const std::vector<std::vector<double>> starts{{1.5 * truth[0], 0.5 * truth[1], 1.5 * truth[2]},
                                                  {0.5 * truth[0], 1.5 * truth[1], 0.5 * truth[2]}};
    for (const auto& start : starts) {
        const auto s = run_levenberg_marquardt(LmSettings{}, start, unbounded_lower(3), unbounded_upper(3), problem);
        CAPTURE(start, s.termination, s.iterations);
        CHECK(s.success);
        for (std::size_t j = 0; j < 3; ++j) CHECK(s.best[j] == Approx(truth[j]).epsilon(1e-8));
        CHECK(s.best_cost < 1e-20);
        CHECK(non_increasing(s.history));
    }
}

TEST_CASE("LM converges on a badly scaled problem as fast as on its rescaled twin", "[lm]") {
    // Inertia 1e-3, damping 1e1, stiffness 1e5 in raw units, and the same model in units
    // of those magnitudes. Moré's scaling makes the iterations (nearly) the same.
    const auto& truth = TorsionalImpulse::truth;
    const std::array<double, 3> off{1.3, 0.7, 0.8};
    TorsionalImpulse bad({1.0, 1.0, 1.0}), twin({1e-3, 10.0, 1e5});
    std::vector<double> x_bad(3), x_twin(3);
    for (std::size_t j = 0; j < 3; ++j) {
        x_bad[j] = off[j] * truth[j] / bad.unit[j];
        x_twin[j] = off[j] * truth[j] / twin.unit[j];
    }
    const auto a = run_levenberg_marquardt(LmSettings{}, x_bad, unbounded_lower(3), unbounded_upper(3), bad);
    const auto b = run_levenberg_marquardt(LmSettings{}, x_twin, unbounded_lower(3), unbounded_upper(3), twin);
    CAPTURE(a.termination, a.iterations, b.termination, b.iterations);
    REQUIRE(a.success);
    REQUIRE(b.success);
    for (std::size_t j = 0; j < 3; ++j) {
        CHECK(a.best[j] * bad.unit[j] == Approx(truth[j]).epsilon(1e-8));
        CHECK(b.best[j] * twin.unit[j] == Approx(truth[j]).epsilon(1e-8));
    }
    CHECK(std::abs(a.iterations - b.iterations) <= 2);
    CHECK(a.iterations < 50);
    CHECK(non_increasing(a.history));
    CHECK(non_increasing(b.history));
}

TEST_CASE("LM ends exactly on a bound when the unconstrained minimum lies outside the box", "[lm]") {
    OptimumOnBound problem;
    const std::vector<double> lower{-kNone, -kNone, 0.0}, upper{2.0, kNone, kNone};
    const double x2 = 799.8 / 200.02;
    for (const auto& start : std::vector<std::vector<double>>{{0.0, 0.0, 1.0}, {-1.0, 5.0, 3.0}, {2.0, 4.0, 0.0}}) {
        const auto s = run_levenberg_marquardt(LmSettings{}, start, lower, upper, problem);
        CAPTURE(start, s.termination, s.iterations);
        CHECK(s.success);
        CHECK(s.best[0] == 2.0);  // exactly on the bounds
        CHECK(s.best[2] == 0.0);
        CHECK(s.best[1] == Approx(x2).epsilon(1e-8));
        CHECK(s.best_cost == Approx(1.0 + 100.0 * (x2 - 4) * (x2 - 4) + (1 + 0.1 * x2) * (1 + 0.1 * x2)));
        CHECK(non_increasing(s.history));
    }
}

TEST_CASE("LM's step that meets a bound is the best one along it, not the free step cut off", "[lm]") {
    // Two strongly correlated parameters (columns 0.95 apart): the free minimum has x0 above
    // its bound. Cut off there, the step would keep x1's value that compensated for the part
    // of x0 cut off; solved again with x0 on the bound, x1 takes its best value for that x0.
    // With almost no damping the first step lands on the constrained minimum.
    LinearResiduals problem;
    problem.A.resize(3, 2);
    problem.A << 1.0, 0.95,  //
        0.95, 1.0,           //
        0.2, -0.1;
    problem.b = Eigen::Vector3d(2.0, 1.0, 0.5);
    const Eigen::VectorXd free_minimum = problem.A.colPivHouseholderQr().solve(problem.b);
    const double bound = 0.5;
    REQUIRE(free_minimum[0] > bound + 1.0);
    // x0 on its bound, x1 the least-squares fit of the rest; the gradient there pushes x0 outward.
    const Eigen::VectorXd a0 = problem.A.col(0), a1 = problem.A.col(1);
    const double x1 = a1.dot(problem.b - a0 * bound) / a1.squaredNorm();
    const Eigen::Vector2d constrained(bound, x1);
    REQUIRE((problem.A.transpose() * (problem.A * constrained - problem.b))[0] < 0);
    const Eigen::Vector2d cut_off(bound, free_minimum[1]);
    REQUIRE(problem.cost(cut_off) > 1.5 * problem.cost(constrained));

    LmSettings settings;
    settings.initial_damping = 1e-12;
    const auto s = run_levenberg_marquardt(settings, {0.0, 0.0}, {-10.0, -10.0}, {bound, 10.0}, problem);
    CAPTURE(s.termination, s.iterations);
    CHECK(s.success);
    REQUIRE(s.history.size() >= 2);
    CHECK(s.history[1].best_cost == Approx(problem.cost(constrained)).epsilon(1e-9));  // the first step
    CHECK(s.best[0] == bound);
    CHECK(s.best[1] == Approx(x1).epsilon(1e-10));
    CHECK(s.iterations <= 3);
}

TEST_CASE("LM's step that meets two bounds puts both on them and solves the third", "[lm]") {
    // Three parameters, the free minimum above x0's upper bound and below x1's lower one.
    LinearResiduals problem;
    problem.A.resize(4, 3);
    problem.A << 1.0, 0.5, 0.3,  //
        0.4, 1.0, -0.4,          //
        0.1, -0.3, 1.0,          //
        0.5, 0.2, 0.6;
    problem.b = Eigen::Vector4d(1.7, -2.05, 1.72, 1.17);  // A (3, −3, 0.5) + (0.05, −0.05, 0.02, −0.03)
    const Eigen::VectorXd free_minimum = problem.A.colPivHouseholderQr().solve(problem.b);
    const double upper0 = 1.0, lower1 = -1.0;
    REQUIRE(free_minimum[0] > upper0);
    REQUIRE(free_minimum[1] < lower1);
    const Eigen::VectorXd a2 = problem.A.col(2);
    const double x2 =
        a2.dot(problem.b - problem.A.col(0) * upper0 - problem.A.col(1) * lower1) / a2.squaredNorm();
    const Eigen::Vector3d constrained(upper0, lower1, x2);
    const Eigen::Vector3d gradient = problem.A.transpose() * (problem.A * constrained - problem.b);
    REQUIRE(gradient[0] < 0);  // both bounds hold at that point: it is the constrained minimum
    REQUIRE(gradient[1] > 0);

    LmSettings settings;
    settings.initial_damping = 1e-12;
    const auto s =
        run_levenberg_marquardt(settings, {0.0, 0.0, 0.0}, {-10.0, lower1, -10.0}, {upper0, 10.0, 10.0}, problem);
    CAPTURE(s.termination, s.iterations, free_minimum.transpose());
    CHECK(s.success);
    REQUIRE(s.history.size() >= 2);
    CHECK(s.history[1].best_cost == Approx(problem.cost(constrained)).epsilon(1e-9));  // the first step
    CHECK(s.best[0] == upper0);
    CHECK(s.best[1] == lower1);
    CHECK(s.best[2] == Approx(x2).epsilon(1e-10));
    CHECK(s.best_cost == Approx(problem.cost(constrained)).epsilon(1e-12));
    CHECK(s.iterations <= 4);
}

TEST_CASE("LM treats failed or non-finite evaluations as rejected steps", "[lm]") {
    FailingDecay problem;
    const std::vector<double> start{1.0, 1.95, 0.25};  // 50 % off the other way
    LmSummary s;
    REQUIRE_NOTHROW(s = run_levenberg_marquardt(LmSettings{}, start, unbounded_lower(3), unbounded_upper(3), problem));
    CAPTURE(s.termination, s.iterations, s.failed_evaluations);
    CHECK(problem.failures >= 2);  // both kinds: false and NaN
    CHECK(s.failed_evaluations == problem.failures);
    CHECK(s.success);
    for (std::size_t j = 0; j < 3; ++j) CHECK(s.best[j] == Approx(ExponentialDecay::truth[j]).epsilon(1e-8));
    CHECK(non_increasing(s.history));
}

TEST_CASE("LM blocked by a failing region says so instead of claiming convergence", "[lm]") {
    // With every b < 1 failing, the path from this start runs into the failing region and
    // stays at its edge (b = 1), where the cost is not stationary.
    FailingDecay problem;
    problem.fail_below = problem.nan_below = 1.0;
    LmSummary s;
    REQUIRE_NOTHROW(s = run_levenberg_marquardt(LmSettings{}, {1.0, 1.95, 0.25}, unbounded_lower(3),
                                                unbounded_upper(3), problem));
    CAPTURE(s.termination, s.iterations, s.best);
    CHECK_FALSE(s.success);
    CHECK(s.best[1] >= 1.0);
    CHECK(s.best_cost < s.initial_cost);
    CHECK(non_increasing(s.history));
}

TEST_CASE("LM reports a start that cannot be evaluated without throwing", "[lm]") {
    FailingDecay problem;
    LmSummary s;
    REQUIRE_NOTHROW(s = run_levenberg_marquardt(LmSettings{}, {2.0, 0.2, 0.5}, unbounded_lower(3),
                                                unbounded_upper(3), problem));
    CHECK(s.termination == "start failed");
    CHECK(s.termination_type == TerminationType::start_failed);
    CHECK_FALSE(s.success);
    CHECK(s.iterations == 0);
    CHECK(std::isinf(s.best_cost));
    CHECK(s.jacobian_at_best.size() == 0);
}

TEST_CASE("LM stops when the progress callback returns false", "[lm]") {
    Rosenbrock problem;
    std::vector<int> seen;
    const auto s = run_levenberg_marquardt(LmSettings{}, {-1.2, 1.0}, unbounded_lower(2), unbounded_upper(2), problem,
                                           [&](const HistoryRow& row) {
                                               seen.push_back(row.iteration);
                                               return row.iteration < 3;
                                           });
    CHECK(s.termination == "stopped");
    CHECK(s.termination_type == TerminationType::stopped);
    CHECK_FALSE(s.success);
    CHECK(s.iterations == 3);
    CHECK(seen == std::vector<int>{0, 1, 2, 3});
    CHECK(s.history.size() == 4);
    CHECK(s.best_cost == s.history.back().best_cost);
}

TEST_CASE("LM honours the iteration limit", "[lm]") {
    Rosenbrock problem;
    LmSettings settings;
    settings.max_iterations = 5;
    const auto s = run_levenberg_marquardt(settings, {-1.2, 1.0}, unbounded_lower(2), unbounded_upper(2), problem);
    CHECK(s.termination == "iteration limit");
    CHECK(s.termination_type == TerminationType::iteration_limit);
    CHECK_FALSE(s.success);
    CHECK(s.iterations == 5);
    CHECK(s.residual_evaluations <= 5);
    CHECK(s.history.size() == 6);
    CHECK(s.best_cost < s.initial_cost);
    CHECK(non_increasing(s.history));

    settings.max_iterations = 0;
    const auto z = run_levenberg_marquardt(settings, {-1.2, 1.0}, unbounded_lower(2), unbounded_upper(2), problem);
    CHECK(z.iterations == 0);
    CHECK(z.residual_evaluations == 0);
    CHECK(z.best == std::vector<double>{-1.2, 1.0});
}

TEST_CASE("LM rejects inconsistent arguments", "[lm]") {
    Rosenbrock problem;
    CHECK_THROWS_AS(run_levenberg_marquardt(LmSettings{}, {1.0, 1.0}, {0.0}, {2.0, 2.0}, problem),
                    std::invalid_argument);
    CHECK_THROWS_AS(run_levenberg_marquardt(LmSettings{}, {1.0, 1.0}, {0.0, 3.0}, {2.0, 2.0}, problem),
                    std::invalid_argument);
    CHECK_THROWS_AS(run_levenberg_marquardt(LmSettings{}, {}, {}, {}, problem), std::invalid_argument);
}

TEST_CASE("LM handles fewer residuals than parameters and parameters held by equal bounds", "[lm]") {
    // r = (x1 + 2 x2 + x3 − 4): any point on that plane is a minimum; x3 is fixed at 1.
    struct Plane : LeastSquaresProblem {
        std::size_t residual_count() const override { return 1; }
        bool residuals(const double* x, double* r) override {
            r[0] = x[0] + 2 * x[1] + x[2] - 4;
            return true;
        }
        bool jacobian(const double* x, double* r, Eigen::MatrixXd& J) override {
            residuals(x, r);
            J << 1.0, 2.0, 1.0;
            return true;
        }
    } problem;
    const auto s = run_levenberg_marquardt(LmSettings{}, {0.0, 0.0, 5.0}, {-kNone, -kNone, 1.0}, {kNone, kNone, 1.0},
                                           problem);
    CAPTURE(s.termination, s.iterations);
    CHECK(s.success);
    CHECK(s.best[2] == 1.0);
    CHECK(s.best[0] + 2 * s.best[1] == Approx(3.0).margin(1e-10));
    CHECK(s.best_cost < 1e-20);
}

namespace {

// One of the problems above, offering the solver `width` residual evaluations side by side
// (run one after the other here: the iterates must not depend on how they are run).
// Counts the residual evaluations, and once `stop_after` of them have run it refuses the
// rest as a stop request would.
struct SideBySide : LeastSquaresProblem {
    LeastSquaresProblem& inner;
    int width;
    long long residual_calls = 0, stop_after = -1;
    bool cut = false;
    SideBySide(LeastSquaresProblem& problem, int w) : inner(problem), width(w) {}
    std::size_t residual_count() const override { return inner.residual_count(); }
    bool residuals(const double* x, double* r) override {
        if ((cut = stop_after >= 0 && residual_calls >= stop_after)) return false;
        ++residual_calls;
        return inner.residuals(x, r);
    }
    bool jacobian(const double* x, double* r, Eigen::MatrixXd& J) override {
        if ((cut = stop_after >= 0 && residual_calls >= stop_after)) return false;
        return inner.jacobian(x, r, J);
    }
    bool stopped() const override { return cut; }
    int concurrent_residuals() const override { return width; }
};

void check_same_path(const LmSummary& a, const LmSummary& b) {
    CHECK(a.best == b.best);
    CHECK(a.best_cost == b.best_cost);
    CHECK(a.iterations == b.iterations);
    CHECK(a.termination == b.termination);
    CHECK(a.residual_evaluations == b.residual_evaluations);
    CHECK(a.jacobian_evaluations == b.jacobian_evaluations);
    CHECK(a.failed_evaluations == b.failed_evaluations);
    REQUIRE(a.history.size() == b.history.size());
    for (std::size_t k = 0; k < a.history.size(); ++k) {
        CHECK(a.history[k].best_cost == b.history[k].best_cost);
        CHECK(a.history[k].evaluations == b.history[k].evaluations);
    }
}

}  // namespace

TEST_CASE("LM with trial steps evaluated ahead, side by side, takes the path of one step at a time", "[lm]") {
    Rosenbrock rosenbrock;
    FailingDecay failing;
    TorsionalImpulse bad({1.0, 1.0, 1.0});
    OptimumOnBound bound;
    struct Case {
        const char* name;
        LeastSquaresProblem& problem;
        std::vector<double> start, lower, upper;
    };
    const std::vector<Case> cases{
        {"Rosenbrock", rosenbrock, {-1.2, 1.0}, unbounded_lower(2), unbounded_upper(2)},
        {"failing decay", failing, {1.0, 1.95, 0.25}, unbounded_lower(3), unbounded_upper(3)},
        {"torsional impulse", bad, {1.2e-3, 8.0, 0.9e5}, unbounded_lower(3), unbounded_upper(3)},
        {"optimum on a bound", bound, {0.0, 0.0, 5.0}, {-kNone, -kNone, 0.0}, {2.0, kNone, kNone}},
    };
    long long taken = 0;
    for (const Case& c : cases) {
        INFO(c.name);
        SideBySide alone(c.problem, 1);
        const LmSummary reference = run_levenberg_marquardt(LmSettings{}, c.start, c.lower, c.upper, alone);
        CHECK(reference.evaluated_ahead == 0);
        const long long rejected = reference.iterations - (reference.jacobian_evaluations - 1);
        for (const int width : {2, 3, 5}) {
            INFO("side by side: " << width);
            SideBySide wide(c.problem, width);
            const LmSummary s = run_levenberg_marquardt(LmSettings{}, c.start, c.lower, c.upper, wide);
            check_same_path(s, reference);
            CHECK(s.taken_ahead <= s.evaluated_ahead);
            CHECK(s.taken_ahead <= rejected);  // only a rejection takes a trial from ahead
            // Every evaluation is either one the solver took or one evaluated ahead in vain.
            CHECK(wide.residual_calls == alone.residual_calls - s.taken_ahead + s.evaluated_ahead);
            if (width == 2) taken += s.taken_ahead;
        }
    }
    CHECK(taken >= 3);  // the rejections of these paths were taken from ahead
}

TEST_CASE("LM stopped while evaluating side by side stays at its last accepted point", "[lm][stop]") {
    Rosenbrock rosenbrock;
    SideBySide alone(rosenbrock, 1);
    const LmSummary reference =
        run_levenberg_marquardt(LmSettings{}, {-1.2, 1.0}, unbounded_lower(2), unbounded_upper(2), alone);
    for (const long long after : {1LL, 4LL, 9LL}) {
        INFO("stop after " << after << " residual evaluations");
        SideBySide wide(rosenbrock, 2);
        wide.stop_after = after;
        const LmSummary s = run_levenberg_marquardt(LmSettings{}, {-1.2, 1.0}, unbounded_lower(2), unbounded_upper(2), wide);
        CHECK(s.termination == "stopped");
        CHECK(s.termination_type == TerminationType::stopped);
        CHECK_FALSE(s.success);
        // The point reached is one the uninterrupted run accepted on its way.
        REQUIRE(s.history.size() <= reference.history.size());
        for (std::size_t k = 0; k < s.history.size(); ++k) CHECK(s.history[k].best_cost == reference.history[k].best_cost);
        CHECK(s.best_cost == s.history.back().best_cost);
    }
}

}  // namespace TVID_UNITY_ID

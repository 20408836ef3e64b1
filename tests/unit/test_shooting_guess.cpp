// The engine's warm-up shooting started from a guess: the solution (angle offset, speed)
// and miss Jacobian of the shooting at nearby parameters, as ResidualEvaluator
// passes them from the point of its last Jacobian to the next trial point, moved to first
// order by the sensitivities' d(a, s)/dp. The guess must save simulations and reach the
// same start to within the shooting's tolerance; a guess that does not converge, or one
// for another window, must leave the result exactly as without it; and the least-squares
// problem must give the same numbers on 1 and 2 threads, and side by side as alone.
#include <catch2/catch.hpp>
#include <algorithm>
#include <cmath>

#include "support/test_files.hpp"
#include "tvid/estimation/residual_evaluator.hpp"
#include "tvid/estimation/forward_sensitivity.hpp"
#include "tvid/estimation/identification_problem.hpp"
#include "tvid/experiment/experiment.hpp"

namespace TVID_UNITY_ID {  // unique to this file in a unity build (tests/CMakeLists.txt)

using namespace tvid;

namespace {

struct Shot {
    bool ok = false;
    std::vector<double> residuals;
    std::vector<SolvedStart> starts;
    std::size_t rhs = 0;
};

Shot shoot(const IdentificationProblem& problem, const std::vector<double>& x,
           const std::vector<ShootingGuess>& guesses = {}) {
    auto ws = problem.make_workspace();
    ws->shooting_guesses = guesses;
    Shot s;
    s.ok = problem.residuals(x.data(), *ws, s.residuals, &s.starts);
    s.rhs = ws->buffers.rhs_evaluations;
    return s;
}

// The noise-free engine experiment, its prior and its estimation window shot from the prior.
struct EngineAtPrior {
    Experiment ex = load_experiment(test::source_dir() / "configs/engine_idle_clean.yaml");
    IdentificationProblem problem{ex};
    std::vector<double> x = problem.initial();
    Shot here = shoot(problem, x);
    /// The guess ResidualEvaluator would keep from `here`.
    ShootingGuess guess() const {
        const Window& w = ex.estimation.at(0);
        const WindowStart& s = here.starts.at(0).start;
        return {w.start, w.first, s.offset, s.speed, s.miss_jacobian};
    }
};

double largest_difference(const std::vector<double>& a, const std::vector<double>& b) {
    double d = 0.0;
    for (std::size_t i = 0; i < a.size(); ++i) d = std::max(d, std::abs(a[i] - b[i]));
    return d;
}

double largest_magnitude(const std::vector<double>& a) {
    double m = 0.0;
    for (double v : a) m = std::max(m, std::abs(v));
    return m;
}

}  // namespace

TEST_CASE("a warm-up shot from the solution at nearby parameters reaches the same start with fewer simulations",
          "[shooting][engine]") {
    const EngineAtPrior engine;
    const IdentificationProblem& problem = engine.problem;
    const std::vector<double>& x = engine.x;
    const Shot& here = engine.here;
    REQUIRE(here.ok);
    REQUIRE(here.starts.at(0).start.shot);
    const ShootingGuess guess = engine.guess();
    CHECK(guess.miss_jacobian[1][0] != 0.0);  // the Jacobian of the last full shooting simulation was kept

    // A trial point as LM takes them near convergence: every parameter 0.1 % off.
    std::vector<double> near = x;
    for (std::size_t j = 0; j < near.size(); ++j) near[j] *= j % 2 == 0 ? 1.001 : 0.999;
    const Shot alone = shoot(problem, near);
    const Shot guessed = shoot(problem, near, {guess});
    REQUIRE(alone.ok);
    REQUIRE(guessed.ok);
    REQUIRE(guessed.starts.at(0).start.shot);
    // Without a guess: coarse and full simulations with tangents (about twice the work per
    // right-hand side), then plain ones; from the guess: plain simulations only.
    INFO("right-hand sides: " << guessed.rhs << " from the guess, " << alone.rhs << " without");
    CHECK(guessed.rhs < alone.rhs);
    // The solution moved with the parameters, and both shootings found it.
    const WindowStart& a = alone.starts[0].start;
    const WindowStart& g = guessed.starts[0].start;
    CHECK(std::abs(a.offset - here.starts[0].start.offset) > 1e-9);
    CHECK(g.offset == Approx(a.offset).margin(1e-10));
    CHECK(g.speed == Approx(a.speed).epsilon(1e-10));
    // Residuals equal to far below anything a fit can see (the shooting's tolerance is 1e-12 rad).
    REQUIRE(guessed.residuals.size() == alone.residuals.size());
    CHECK(largest_difference(guessed.residuals, alone.residuals) < 1e-8 * largest_magnitude(alone.residuals));
}

TEST_CASE("a shooting guess from parameters further off still reaches the same start",
          "[shooting][engine]") {
    const EngineAtPrior engine;
    const IdentificationProblem& problem = engine.problem;
    const std::vector<double>& x = engine.x;
    REQUIRE(engine.here.ok);
    for (const double off : {0.01, 0.1}) {
        std::vector<double> far = x;
        for (std::size_t j = 0; j < far.size(); ++j) far[j] *= j % 2 == 0 ? 1.0 + off : 1.0 - off;
        const Shot alone = shoot(problem, far);
        const Shot guessed = shoot(problem, far, {engine.guess()});
        INFO("parameters " << off * 100 << " % off");
        REQUIRE(alone.ok);
        REQUIRE(guessed.ok);
        CHECK(guessed.starts.at(0).start.offset == Approx(alone.starts.at(0).start.offset).margin(1e-10));
        CHECK(largest_difference(guessed.residuals, alone.residuals) < 1e-8 * largest_magnitude(alone.residuals));
    }
}

TEST_CASE("a shooting guess that does not converge, or belongs to another window, changes nothing",
          "[shooting][engine]") {
    const EngineAtPrior engine;
    const IdentificationProblem& problem = engine.problem;
    const std::vector<double>& x = engine.x;
    const Shot& here = engine.here;
    REQUIRE(here.ok);

    SECTION("a miss Jacobian of the wrong sign: the chord steps diverge, the shooting starts over") {
        ShootingGuess wrong = engine.guess();
        wrong.offset += 1e-3;
        for (auto& row : wrong.miss_jacobian)
            for (double& v : row) v = -v;
        const Shot s = shoot(problem, x, {wrong});
        REQUIRE(s.ok);
        CHECK(s.residuals == here.residuals);  // bit for bit: the shooting as without a guess
        CHECK(s.rhs > here.rhs);               // after the attempt
    }
    SECTION("a singular miss Jacobian") {
        ShootingGuess flat = engine.guess();
        flat.offset += 1e-3;
        for (auto& row : flat.miss_jacobian)
            for (double& v : row) v = 0.0;
        const Shot s = shoot(problem, x, {flat});
        REQUIRE(s.ok);
        CHECK(s.residuals == here.residuals);
    }
    SECTION("a guess for a window that starts elsewhere is not used") {
        ShootingGuess other = engine.guess();
        other.start += 1;
        const Shot s = shoot(problem, x, {other});
        REQUIRE(s.ok);
        CHECK(s.residuals == here.residuals);
        CHECK(s.rhs == here.rhs);
    }
}

TEST_CASE("least squares with shooting guesses give the same residuals and Jacobians on 1 and 2 threads",
          "[shooting][engine][lm][heavy]") {
    const Experiment ex = load_experiment(test::source_dir() / "configs/engine_idle_clean.yaml");
    const IdentificationProblem problem(ex);
    const std::vector<double> x = problem.initial();
    std::vector<double> trial = x;
    for (std::size_t j = 0; j < trial.size(); ++j) trial[j] *= 1.0 + 0.002 * static_cast<double>(j + 1);
    const auto n = static_cast<Eigen::Index>(estimation_residual_count(ex));
    const auto m = static_cast<Eigen::Index>(x.size());

    struct Run {
        std::vector<double> r, r_trial;
        Eigen::MatrixXd J, J_trial;
    };
    auto run = [&](int threads) {
        ResidualEvaluator ls(problem, EvaluatorOptions(threads).with_jacobian(JacobianKind::sensitivity));
        Run out{std::vector<double>(static_cast<std::size_t>(n)), std::vector<double>(static_cast<std::size_t>(n)),
                Eigen::MatrixXd(n, m), Eigen::MatrixXd(n, m)};
        REQUIRE(ls.jacobian(x.data(), out.r.data(), out.J));        // keeps the guesses
        REQUIRE(ls.residuals(trial.data(), out.r_trial.data()));    // shoots from them
        REQUIRE(ls.jacobian(trial.data(), out.r_trial.data(), out.J_trial));
        return out;
    };
    const Run one = run(1), two = run(2);
    CHECK(one.r == two.r);
    CHECK(one.r_trial == two.r_trial);
    CHECK(one.J == two.J);
    CHECK(one.J_trial == two.J_trial);
    // And the trial's residuals are those of the shooting without a guess, to its tolerance.
    const Shot alone = shoot(problem, trial);
    REQUIRE(alone.ok);
    CHECK(largest_difference(one.r_trial, alone.residuals) < 1e-8 * largest_magnitude(alone.residuals));
}

TEST_CASE("the sensitivities' d(a, s)/dp of the warm-up shooting agree with differences and predict the start",
          "[shooting][engine][sensitivity][heavy]") {
    const EngineAtPrior engine;
    const IdentificationProblem& problem = engine.problem;
    const std::vector<double>& x = engine.x;
    REQUIRE(engine.here.ok);
    const std::size_t m = x.size();
    const auto n = static_cast<Eigen::Index>(estimation_residual_count(engine.ex));
    const ForwardSensitivity sensitivity(problem);
    auto ws = sensitivity.make_workspace();
    Eigen::MatrixXd J(n, static_cast<Eigen::Index>(m)), slopes = Eigen::MatrixXd::Constant(2, static_cast<Eigen::Index>(m), -1.0);
    REQUIRE(sensitivity.jacobian_columns(x.data(), 0, m, *ws, J, nullptr, &slopes));
    // The same numbers from two blocks of columns (as on two threads).
    Eigen::MatrixXd halves = Eigen::MatrixXd::Zero(2, static_cast<Eigen::Index>(m));
    REQUIRE(sensitivity.jacobian_columns(x.data(), 0, m / 2, *ws, J, nullptr, &halves));
    REQUIRE(sensitivity.jacobian_columns(x.data(), m / 2, m, *ws, J, nullptr, &halves));
    CHECK(halves == slopes);

    // Central differences of the shot start itself.
    for (std::size_t j = 0; j < m; ++j) {
        const double h = 1e-4 * std::abs(x[j]);
        std::vector<double> up = x, down = x;
        up[j] += h;
        down[j] -= h;
        const Shot a = shoot(problem, up), b = shoot(problem, down);
        REQUIRE(a.ok);
        REQUIRE(b.ok);
        const double da = (a.starts.at(0).start.offset - b.starts.at(0).start.offset) / (2 * h);
        const double ds = (a.starts.at(0).start.speed - b.starts.at(0).start.speed) / (2 * h);
        INFO("parameter " << j);
        CHECK(slopes(0, static_cast<Eigen::Index>(j)) == Approx(da).epsilon(1e-3).margin(1e-3 * slopes.row(0).cwiseAbs().maxCoeff()));
        CHECK(slopes(1, static_cast<Eigen::Index>(j)) == Approx(ds).epsilon(1e-3).margin(1e-3 * slopes.row(1).cwiseAbs().maxCoeff()));
    }

    // At a trial point 1 % off, the first-order prediction lands far closer to the start
    // shot there than the guess's own solution, and the shooting from it needs fewer
    // simulations.
    std::vector<double> trial = x;
    for (std::size_t j = 0; j < m; ++j) trial[j] *= j % 2 == 0 ? 1.01 : 0.99;
    ShootingGuess predicted = engine.guess();
    for (std::size_t j = 0; j < m; ++j) {
        predicted.offset += slopes(0, static_cast<Eigen::Index>(j)) * (trial[j] - x[j]);
        predicted.speed += slopes(1, static_cast<Eigen::Index>(j)) * (trial[j] - x[j]);
    }
    const Shot alone = shoot(problem, trial), plain = shoot(problem, trial, {engine.guess()}),
               moved = shoot(problem, trial, {predicted});
    REQUIRE(alone.ok);
    REQUIRE(plain.ok);
    REQUIRE(moved.ok);
    const WindowStart& solution = alone.starts.at(0).start;
    const WindowStart& before = engine.here.starts.at(0).start;
    CHECK(std::abs(predicted.offset - solution.offset) < 0.05 * std::abs(before.offset - solution.offset));
    CHECK(std::abs(predicted.speed - solution.speed) < 0.05 * std::abs(before.speed - solution.speed));
    INFO("right-hand sides: " << moved.rhs << " from the prediction, " << plain.rhs << " from the guess alone");
    CHECK(moved.rhs < plain.rhs);
    CHECK(moved.starts.at(0).start.offset == Approx(solution.offset).margin(1e-10));
    CHECK(largest_difference(moved.residuals, alone.residuals) < 1e-8 * largest_magnitude(alone.residuals));
}

TEST_CASE("least squares evaluated side by side give the residuals of each point alone and reuse them",
          "[shooting][engine][lm][heavy]") {
    const Experiment ex = load_experiment(test::source_dir() / "configs/engine_idle_clean.yaml");
    const IdentificationProblem problem(ex);
    const std::vector<double> x = problem.initial();
    const std::size_t n = estimation_residual_count(ex);
    const auto m = static_cast<Eigen::Index>(x.size());
    std::vector<double> near = x, further = x;
    for (std::size_t j = 0; j < x.size(); ++j) {
        near[j] *= 1.0 + 0.001 * static_cast<double>(j + 1);
        further[j] *= 1.0 + 0.003 * static_cast<double>(j + 1);
    }
    std::vector<double> r0(n), r_near(n), r_further(n), r_jac(n);
    Eigen::MatrixXd J(static_cast<Eigen::Index>(n), m);

    ResidualEvaluator one(problem, EvaluatorOptions(1).with_jacobian(JacobianKind::sensitivity));  // one at a time
    REQUIRE(one.concurrent_residuals() == 1);
    REQUIRE(one.jacobian(x.data(), r0.data(), J));
    REQUIRE(one.residuals(near.data(), r_near.data()));
    REQUIRE(one.residuals(further.data(), r_further.data()));

    ResidualEvaluator two(problem, EvaluatorOptions(2).with_jacobian(JacobianKind::sensitivity));
    REQUIRE(two.concurrent_residuals() == 2);
    REQUIRE(two.jacobian(x.data(), r0.data(), J));
    std::vector<double> a(n), b(n);
    const double* points[2] = {near.data(), further.data()};
    double* out[2] = {a.data(), b.data()};
    char ok[2] = {0, 0}, stopped[2] = {1, 1};
    two.residuals_side_by_side(2, points, out, ok, stopped);
    REQUIRE(ok[0]);
    REQUIRE(ok[1]);
    CHECK_FALSE(stopped[0]);
    CHECK_FALSE(stopped[1]);
    CHECK(a == r_near);  // bit for bit: the same guesses, whichever thread
    CHECK(b == r_further);
    // A Jacobian at the second point takes its residuals and solved start from there:
    // the sensitivity blocks are the only simulations it runs.
    const long long before = two.simulations();
    REQUIRE(two.jacobian(further.data(), r_jac.data(), J));
    CHECK(two.simulations() - before == 2);
    CHECK(r_jac == r_further);
}

}  // namespace TVID_UNITY_ID

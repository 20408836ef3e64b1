// Parameter scaling (`scale: log | linear`): the optimizers search ln p for a log-scaled
// parameter. The mapping and its derivatives, the box sampled evenly per decade, linear
// scaling passing every value through bit for bit, the same optimum in either scaling, and
// the interval of a log-scaled parameter formed in ln p.
#include <catch2/catch.hpp>
#include <array>
#include <cmath>
#include <nlohmann/json.hpp>

#include "support/sinusoid_fit.hpp"
#include "support/test_files.hpp"
#include "tvid/estimation/identification_problem.hpp"
#include "tvid/experiment/experiment.hpp"
#include "tvid/fit/fit_run.hpp"
#include "tvid/fit/optimizers/search_box.hpp"
#include "tvid/optim/multistart.hpp"
#include "tvid/optim/parameter_scaling.hpp"

namespace TVID_UNITY_ID {  // unique to this file in a unity build (tests/CMakeLists.txt)

using namespace tvid;
using tvid::test::SinusoidFit;

namespace {

const std::vector<ParameterScale> kLogLinear = {ParameterScale::log, ParameterScale::linear};

// The decade of p in a box starting at 1e-5: 0 for [1e-5, 1e-4), …, 4 for [0.1, 1].
int decade(double p) { return std::min(4, static_cast<int>(std::floor(std::log10(p) + 5.0))); }

}  // namespace

TEST_CASE("scaling maps log parameters to their logarithm and back, within the bounds", "[scale]") {
    const ParameterScaling s(kLogLinear, {1e-5, -3.0}, {1.0, 3.0});
    CHECK_FALSE(s.linear());
    CHECK(s.to_search(0, 1e-3) == Approx(std::log(1e-3)).epsilon(1e-15));
    CHECK(s.to_search(1, -2.5) == -2.5);
    CHECK(s.to_parameter(0, std::log(0.02)) == Approx(0.02).epsilon(1e-15));
    CHECK(s.to_parameter(0, s.to_search(0, 1.0)) == 1.0);    // a bound's image is the bound
    CHECK(s.to_parameter(0, s.to_search(0, 1e-5)) == 1e-5);
    const SearchBox box = s.to_search(SearchBox{{1e-5, -3.0}, {1.0, 3.0}, {1e-4, -1.0}, {0.1, 1.0}});
    CHECK(box.lower[0] == Approx(std::log(1e-5)));
    CHECK(box.upper[0] == 0.0);
    CHECK(box.range_lower[0] == Approx(std::log(1e-4)));
    CHECK(box.range_upper[0] == Approx(std::log(0.1)));
    CHECK(box.lower[1] == -3.0);
    CHECK(box.range_upper[1] == 1.0);
    // An absent upper bound stays absent.
    const ParameterScaling open(kLogLinear, {1e-5, -1e300}, {1e300, 1e300});
    const SearchBox unbounded = open.to_search(SearchBox{{1e-5, -1e300}, {1e300, 1e300}, {1e-4, 0.0}, {1.0, 1.0}});
    CHECK(unbounded.upper[0] == 1e300);
    CHECK(unbounded.lower[1] == -1e300);
    CHECK(open.to_parameter(0, 800.0) == std::numeric_limits<double>::infinity());
    // A log parameter whose box reaches 0 has no logarithm.
    CHECK_THROWS_AS(ParameterScaling(kLogLinear, {0.0, 0.0}, {1.0, 1.0}), std::invalid_argument);
}

TEST_CASE("log scaling samples a five-decade box evenly per decade", "[scale][multistart]") {
    // Multistart's Latin hypercube of 100 starts in the box [1e-5, 1] of the first parameter.
    const SearchBox box{{1e-5, 1e-5}, {1.0, 1.0}, {1e-5, 1e-5}, {1.0, 1.0}};
    MultistartSettings settings;
    settings.starts = 100;
    settings.seed = 7;
    const ParameterScaling log_first(kLogLinear, box.lower, box.upper);
    const std::vector<double> u = multistart_points(settings, log_first.to_search(box));
    std::array<int, 5> log_count{}, linear_count{};
    for (std::size_t i = 0; i < 100; ++i) {
        const double p0 = log_first.to_parameter(0, u[2 * i]), p1 = log_first.to_parameter(1, u[2 * i + 1]);
        CHECK(p0 >= 1e-5);
        CHECK(p0 <= 1.0);
        ++log_count[static_cast<std::size_t>(decade(p0))];
        ++linear_count[static_cast<std::size_t>(decade(p1))];
    }
    // 20 strata of the hypercube in every decade: exactly 20 starts each.
    CHECK(log_count == std::array<int, 5>{20, 20, 20, 20, 20});
    // Linear: the top decade takes about 90 % of the starts, the lowest none.
    CHECK(linear_count[4] >= 89);
    CHECK(linear_count[0] == 0);
}

TEST_CASE("the adapters hand the model p and give derivatives in ln p", "[scale]") {
    SinusoidFit fit;
    const ParameterScaling s(kLogLinear, {0.1, 0.1}, {10.0, 10.0});
    ScaledLeastSquares scaled(fit, s);
    const std::vector<double> p = {1.2, 2.9};
    const std::vector<double> u = s.to_search(p);
    const auto n = static_cast<Eigen::Index>(fit.residual_count());
    Eigen::VectorXd r_direct(n), r_scaled(n);
    Eigen::MatrixXd J_direct(n, 2), J_scaled(n, 2);
    REQUIRE(fit.jacobian(p.data(), r_direct.data(), J_direct));
    REQUIRE(scaled.jacobian(u.data(), r_scaled.data(), J_scaled));
    CHECK((r_scaled - r_direct).cwiseAbs().maxCoeff() < 1e-12);
    // ∂r/∂ln a = a ∂r/∂a; ∂r/∂ω untouched.
    CHECK((J_scaled.col(0) - p[0] * J_direct.col(0)).cwiseAbs().maxCoeff() < 1e-12);
    CHECK((J_scaled.col(1) - J_direct.col(1)).cwiseAbs().maxCoeff() < 1e-12);
    // The same by central differences in u.
    const double h = 1e-6;
    std::vector<double> up = u, um = u;
    up[0] += h;
    um[0] -= h;
    Eigen::VectorXd rp(n), rm(n);
    REQUIRE(scaled.residuals(up.data(), rp.data()));
    REQUIRE(scaled.residuals(um.data(), rm.data()));
    CHECK(((rp - rm) / (2 * h) - J_scaled.col(0)).cwiseAbs().maxCoeff() < 1e-6);
    // The swarm's candidates are scored at p.
    ScaledCandidateEvaluator candidates(fit, s);
    double scaled_cost = 0.0, direct_cost = 0.0;
    candidates.evaluate(u.data(), 1, 2, &scaled_cost);
    fit.evaluate(p.data(), 1, 2, &direct_cost);
    CHECK(scaled_cost == Approx(direct_cost).epsilon(1e-12));
}

TEST_CASE("linear scaling passes every value through: LM's path is the same bit for bit", "[scale]") {
    const std::vector<ParameterScale> linear = {ParameterScale::linear, ParameterScale::linear};
    const ParameterScaling s(linear, {0.0, 0.1}, {10.0, 10.0});
    CHECK(s.linear());
    SinusoidFit direct_fit, scaled_fit;
    ScaledLeastSquares scaled(scaled_fit, s);
    const LmSummary direct = run_levenberg_marquardt(LmSettings{}, {1.0, 2.9}, {0.0, 0.1}, {10.0, 10.0}, direct_fit);
    LmSummary through = run_levenberg_marquardt(LmSettings{}, {1.0, 2.9}, {0.0, 0.1}, {10.0, 10.0}, scaled);
    to_parameters(s, through);
    CHECK(through.best == direct.best);
    CHECK(through.best_cost == direct.best_cost);
    CHECK(through.iterations == direct.iterations);
    CHECK(through.jacobian_at_best == direct.jacobian_at_best);
}

TEST_CASE("LM in ln p reaches the optimum of LM in p", "[scale]") {
    SinusoidFit fit;
    const ParameterScaling s({ParameterScale::log, ParameterScale::log}, {0.01, 0.1}, {100.0, 10.0});
    ScaledLeastSquares scaled(fit, s);
    const SearchBox box = s.to_search(SearchBox{{0.01, 0.1}, {100.0, 10.0}, {}, {}});
    LmSummary lm = run_levenberg_marquardt(LmSettings{}, s.to_search({0.2, 2.9}), box.lower, box.upper, scaled);
    to_parameters(s, lm);
    CHECK(lm.success);
    CHECK(lm.best[0] == Approx(SinusoidFit::kAmplitude).epsilon(1e-9));
    CHECK(lm.best[1] == Approx(SinusoidFit::kFrequency).epsilon(1e-9));
    // The Jacobian at the best is ∂r/∂p again (the sinusoid's own there).
    const auto n = static_cast<Eigen::Index>(fit.residual_count());
    Eigen::VectorXd r(n);
    Eigen::MatrixXd J(n, 2);
    REQUIRE(fit.jacobian(lm.best.data(), r.data(), J));
    CHECK((lm.jacobian_at_best - J).cwiseAbs().maxCoeff() < 1e-9 * J.cwiseAbs().maxCoeff());
}

namespace {

// The noise-free CVT tip-in with ρ1 fixed at the truth and the other eight parameters
// started 3 % above it (well posed: every direction determined), fitted by LM; `log`:
// every parameter whose truth is positive on scale log, with a positive min.
std::vector<Override> cvt_overrides(bool log) {
    const auto truth =
        nlohmann::json::parse(test::read_text(test::source_dir() / "data/cvt/truth.json"))["parameters"];
    // stol 0: both paths to the tolerances' end, to compare the optimum to 1e-6 (the
    // statistical test would stop each within a tenth of a standard error, apart by more).
    std::vector<Override> overrides = {
        {"estimation.optimizer", "lm"}, {"estimation.cost", "l2"}, {"estimation.lm.stol", "0"}};
    for (auto it = truth.begin(); it != truth.end(); ++it) {
        char value[64];
        std::snprintf(value, sizeof value, "%.17g", it.value().get<double>() * (it.key() == "rho1" ? 1.0 : 1.03));
        overrides.push_back({"parameters." + it.key() + (it.key() == "rho1" ? "" : ".init"), value});
        if (!log || it.key() == "rho1" || it.value().get<double>() < 0) continue;
        overrides.push_back({"parameters." + it.key() + ".scale", "log"});
        overrides.push_back({"parameters." + it.key() + ".min", "1e-6"});
    }
    return overrides;
}

FitResult cvt_fit(bool log, std::vector<Override> extra = {}, int threads = 1) {
    std::vector<Override> overrides = cvt_overrides(log);
    overrides.insert(overrides.end(), extra.begin(), extra.end());
    const Experiment ex = load_experiment(test::source_dir() / "configs/cvt_tipin_clean.yaml", overrides);
    const IdentificationProblem problem(ex);
    REQUIRE(problem.dimension() == 8);
    FitOptions options;
    options.threads = threads;
    FitResult fit = run_fit(problem, options);
    REQUIRE(fit.success);
    return fit;
}

}  // namespace

TEST_CASE("log scaling gives the same optimum as linear scaling on a well-posed problem", "[scale][uncertainty]") {
    const FitResult linear = cvt_fit(false);
    const FitResult log = cvt_fit(true);
    CHECK(log.run.converged);
    CHECK(linear.run.converged);
    REQUIRE(log.best_params.size() == linear.best_params.size());
    for (std::size_t i = 0; i < log.best_params.size(); ++i) {
        INFO("parameter " << i);
        CHECK(log.best_params[i] == Approx(linear.best_params[i]).epsilon(1e-6).margin(1e-9));
    }
    // Each took its own path: the log fit is not the linear one in disguise.
    CHECK(log.run.history.size() != 0);
    CHECK(log.best_free != linear.best_free);
    CHECK(log.evaluation.cost == Approx(linear.evaluation.cost).epsilon(1e-3).margin(1e-20));

    // The intervals: symmetric in p for a linear parameter, in ln p for a log one (d_ds,
    // negative, stays linear).
    REQUIRE(log.uncertainty.available);
    REQUIRE(linear.uncertainty.available);
    for (std::size_t j = 0; j < log.best_free.size(); ++j) {
        INFO("free parameter " << j);
        const double p = log.best_free[j];
        const double lo = log.uncertainty.ci_low[j], hi = log.uncertainty.ci_high[j];
        REQUIRE(std::isfinite(lo));
        if (p > 0) {
            CHECK(lo > 0);
            CHECK(lo * hi == Approx(p * p).epsilon(1e-12));      // p / lo = hi / p
            CHECK(hi - p > p - lo);                              // asymmetric in p
            // The same relative standard error in either scaling (the same Jacobian).
            CHECK(log.uncertainty.std_error[j] / p ==
                  Approx(linear.uncertainty.std_error[j] / linear.best_free[j]).epsilon(1e-4));
        } else {
            CHECK(hi - p == Approx(p - lo).epsilon(1e-12));
        }
        CHECK(linear.uncertainty.ci_high[j] - linear.best_free[j] ==
              Approx(linear.best_free[j] - linear.uncertainty.ci_low[j]).epsilon(1e-12));
    }
}

TEST_CASE("log-scaled multistart and swarm give the same result on 1 and 2 threads", "[scale][multistart]") {
    const auto range = [](const char* name, const char* box) { return Override{std::string("parameters.") + name + ".range", box}; };
    // Boxes of three decades around the truth (k± ~ 3e3 and 9e3, c± ~ 4 and 19, μ ~ 3.6e-3).
    const std::vector<Override> boxes = {range("k_minus", "[1.0e2, 1.0e5]"), range("k_plus", "[1.0e2, 1.0e5]"),
                                         range("c_minus", "[0.1, 100]"),     range("c_plus", "[0.1, 100]"),
                                         range("mu", "[1.0e-4, 0.1]")};
    SECTION("multistart") {
        std::vector<Override> extra = boxes;
        extra.push_back({"estimation.optimizer", "multistart"});
        extra.push_back({"estimation.multistart", "{ starts: 4, seed: 3, max_iterations: 5 }"});
        const FitResult one = cvt_fit(true, extra, 1), two = cvt_fit(true, extra, 2);
        CHECK(one.best_free == two.best_free);
        CHECK(one.run.best_cost == two.run.best_cost);
        CHECK(one.run.name == "multistart");
        REQUIRE(one.run.starts.size() == 4);
        double lowest = 1e300;
        for (std::size_t i = 0; i < 4; ++i) {
            CHECK(one.run.starts[i].initial == two.run.starts[i].initial);
            // Starts reported as parameters, inside the range box (k_minus, the second free one).
            CHECK(one.run.starts[i].initial[1] >= 1.0e2);
            CHECK(one.run.starts[i].initial[1] <= 1.0e5);
            lowest = std::min(lowest, one.run.starts[i].initial[1]);
        }
        // One start in each quarter of the three decades: the lowest below 10^2.75 (linear
        // sampling would put one there with a chance of 2 %).
        CHECK(lowest < 562.4);
    }
    SECTION("swarm") {
        std::vector<Override> extra = boxes;
        extra.push_back({"estimation.optimizer", "pso"});
        extra.push_back({"estimation.pso", "{ start: latin_hypercube, particles: 8, iterations: 3, seed: 2 }"});
        const FitResult one = cvt_fit(true, extra, 1), two = cvt_fit(true, extra, 2);
        CHECK(one.run.name == "pso");
        CHECK(one.best_free == two.best_free);
        CHECK(one.run.best_cost == two.run.best_cost);
        // The best particle reported as parameters: k_minus in thousands, not its logarithm (< 14).
        CHECK(one.best_free[1] > 20.0);
    }
}

}  // namespace TVID_UNITY_ID

// The uncertainty at the optimum from the Jacobian a least-squares fit already computed
// there: the same standard errors, intervals and rank as computing it again, used only
// where it is the sensitivities' Jacobian of the right shape.
#include <catch2/catch.hpp>
#include <cmath>
#include <nlohmann/json.hpp>

#include "support/test_files.hpp"
#include "tvid/estimation/residual_evaluator.hpp"
#include "tvid/analysis/uncertainty.hpp"
#include "tvid/experiment/experiment.hpp"
#include "tvid/fit/fit_run.hpp"

namespace TVID_UNITY_ID {  // unique to this file in a unity build (tests/CMakeLists.txt)

using namespace tvid;

namespace {

// The noise-free CVT tip-in with ρ1 fixed (no scaling symmetry: every direction
// determined) and the other eight parameters started 3 % above the truth.
Experiment cvt_near_truth(std::vector<Override> extra = {}) {
    const auto truth = nlohmann::json::parse(test::read_text(test::source_dir() / "data/cvt/truth.json"))["parameters"];
    std::vector<Override> overrides = {{"estimation.optimizer", "lm"}, {"estimation.cost", "l2"}};
    for (auto it = truth.begin(); it != truth.end(); ++it) {
        char value[64];
        std::snprintf(value, sizeof value, "%.17g", it.value().get<double>() * (it.key() == "rho1" ? 1.0 : 1.03));
        overrides.push_back({"parameters." + it.key() + (it.key() == "rho1" ? "" : ".init"), value});
    }
    overrides.insert(overrides.end(), extra.begin(), extra.end());
    return load_experiment(test::source_dir() / "configs/cvt_tipin_clean.yaml", overrides);
}

struct ResidualsAndJacobian {
    Eigen::VectorXd r;
    Eigen::MatrixXd J;
};

ResidualsAndJacobian least_squares_jacobian(const IdentificationProblem& problem, const std::vector<double>& at) {
    ResidualEvaluator ls(problem, EvaluatorOptions(1));
    ResidualsAndJacobian out{Eigen::VectorXd(static_cast<Eigen::Index>(ls.residual_count())),
                             Eigen::MatrixXd(static_cast<Eigen::Index>(ls.residual_count()),
                                             static_cast<Eigen::Index>(problem.dimension()))};
    REQUIRE(ls.jacobian(at.data(), out.r.data(), out.J));
    return out;
}

void check_same(const ParameterUncertainty& a, const ParameterUncertainty& b, double relative) {
    REQUIRE(a.available);
    REQUIRE(b.available);
    CHECK(a.residuals == b.residuals);
    CHECK(a.rank == b.rank);
    CHECK(a.condition_number == Approx(b.condition_number).epsilon(relative));
    REQUIRE(a.std_error.size() == b.std_error.size());
    for (std::size_t j = 0; j < a.std_error.size(); ++j) {
        INFO("parameter " << j);
        CHECK(a.determined[j] == b.determined[j]);
        CHECK(a.std_error[j] == Approx(b.std_error[j]).epsilon(relative));
        CHECK(a.ci_low[j] == Approx(b.ci_low[j]).epsilon(relative));
        for (std::size_t k = 0; k < a.std_error.size(); ++k)
            CHECK(a.correlation[j][k] == Approx(b.correlation[j][k]).epsilon(relative).margin(relative));
    }
}

}  // namespace

TEST_CASE("the uncertainty from a given sensitivity Jacobian equals the one computed again", "[uncertainty]") {
    const Experiment ex = cvt_near_truth();
    const IdentificationProblem problem(ex);
    REQUIRE(problem.dimension() == 8);
    const std::vector<double> at = problem.initial();
    const ResidualsAndJacobian lj = least_squares_jacobian(problem, at);

    const ParameterUncertainty computed = estimate_uncertainty(problem, at);
    const ParameterUncertainty given = estimate_uncertainty(problem, at, {&lj.J, lj.r.squaredNorm()});
    REQUIRE(computed.rank == 8);
    check_same(given, computed, 1e-9);

    SECTION("the given Jacobian is the one used: twice J halves every standard error") {
        const Eigen::MatrixXd doubled = 2.0 * lj.J;
        const ParameterUncertainty u = estimate_uncertainty(problem, at, {&doubled, lj.r.squaredNorm()});
        for (std::size_t j = 0; j < 8; ++j) CHECK(u.std_error[j] == Approx(0.5 * computed.std_error[j]).epsilon(1e-9));
    }
    SECTION("and Σe²: four times it doubles them") {
        const ParameterUncertainty u = estimate_uncertainty(problem, at, {&lj.J, 4.0 * lj.r.squaredNorm()});
        for (std::size_t j = 0; j < 8; ++j) CHECK(u.std_error[j] == Approx(2.0 * computed.std_error[j]).epsilon(1e-9));
    }
    SECTION("a Jacobian of the wrong shape or with non-finite entries is computed again") {
        const Eigen::MatrixXd narrow = lj.J.leftCols(7);
        check_same(estimate_uncertainty(problem, at, {&narrow, lj.r.squaredNorm()}), computed, 0.0);
        Eigen::MatrixXd broken = 2.0 * lj.J;
        broken(3, 2) = std::nan("");
        check_same(estimate_uncertainty(problem, at, {&broken, lj.r.squaredNorm()}), computed, 0.0);
        check_same(estimate_uncertainty(problem, at, {&lj.J, std::nan("")}), computed, 0.0);
    }
}

TEST_CASE("with finite differences asked for, a given Jacobian is the evaluator's own and is used", "[uncertainty]") {
    // The uncertainty forms its Jacobian with the same ResidualEvaluator, step rule and all,
    // as a least-squares fit with `jacobian: fd`: the fit's Jacobian gives the same figures
    // as one formed afresh, and a given one (here doubled, to tell) is what is used.
    const Experiment ex = cvt_near_truth({{"estimation.lm.jacobian", "fd"}});
    const IdentificationProblem problem(ex);
    const std::vector<double> at = problem.initial();
    const ResidualsAndJacobian lj = least_squares_jacobian(problem, at);
    const ParameterUncertainty fresh = estimate_uncertainty(problem, at);
    check_same(estimate_uncertainty(problem, at, {&lj.J, lj.r.squaredNorm()}), fresh, 1e-12);
    const Eigen::MatrixXd doubled = 2.0 * lj.J;
    const ParameterUncertainty halved = estimate_uncertainty(problem, at, {&doubled, lj.r.squaredNorm()});
    REQUIRE(halved.available);
    for (std::size_t j = 0; j < halved.std_error.size(); ++j)
        if (std::isfinite(fresh.std_error[j])) CHECK(halved.std_error[j] == Approx(0.5 * fresh.std_error[j]).epsilon(1e-9));
}

TEST_CASE("an LM fit reports the uncertainty of its last Jacobian, equal to one computed at its optimum",
          "[uncertainty][lm]") {
    // Three iterations: not converged, but the report still describes the point it stopped at.
    const Experiment ex = cvt_near_truth({{"estimation.lm.max_iterations", "3"}});
    const IdentificationProblem problem(ex);
    FitOptions options;
    options.threads = 2;
    const FitResult fit = run_fit(problem, options);
    REQUIRE(fit.success);
    REQUIRE(fit.summary_of<LmSummary>()->best == fit.best_free);
    REQUIRE(fit.run.jacobian_at_best.cols() == 8);
    check_same(fit.uncertainty, estimate_uncertainty(problem, fit.best_free), 1e-9);
}

}  // namespace TVID_UNITY_ID

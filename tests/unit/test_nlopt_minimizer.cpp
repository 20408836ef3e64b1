// NLopt by name on small problems with a known optimum: a local derivative-free, a local
// gradient-based and global algorithms reach it; failed evaluations, the progress stop,
// the seed and bad settings behave as documented.
#include <catch2/catch.hpp>
#include <cmath>
#include <limits>
#include <numbers>
#include <stdexcept>
#include <vector>

#include "tvid/optim/nlopt_algorithms.hpp"
#include "tvid/optim/nlopt_minimizer.hpp"

namespace TVID_UNITY_ID {  // unique to this file in a unity build (tests/CMakeLists.txt)

using namespace tvid;

namespace {

// Rosenbrock's function 100 (y − x²)² + (1 − x)², minimum 0 at (1, 1), with its gradient.
struct Rosenbrock : DifferentiableCost {
    long long gradients = 0;
    double value(const double* x) override { return 100.0 * std::pow(x[1] - x[0] * x[0], 2) + std::pow(1.0 - x[0], 2); }
    double value_and_gradient(const double* x, double* g) override {
        ++gradients;
        g[0] = -400.0 * x[0] * (x[1] - x[0] * x[0]) - 2.0 * (1.0 - x[0]);
        g[1] = 200.0 * (x[1] - x[0] * x[0]);
        return value(x);
    }
};

// Rastrigin's function in 2-D, Σ x² − 10 cos(2π x) + 10: a local minimum near every integer
// point, the global one 0 at the origin.
struct Rastrigin : DifferentiableCost {
    double value(const double* x) override {
        double f = 20.0;
        for (int j = 0; j < 2; ++j) f += x[j] * x[j] - 10.0 * std::cos(2.0 * std::numbers::pi * x[j]);
        return f;
    }
    double value_and_gradient(const double* x, double* g) override {
        for (int j = 0; j < 2; ++j) g[j] = 2.0 * x[j] + 20.0 * std::numbers::pi * std::sin(2.0 * std::numbers::pi * x[j]);
        return value(x);
    }
};

// A quadratic whose model "fails to simulate" (returns +inf) for x0 > 2.5; its minimum
// (1, −2) lies inside the region that works.
struct FailingQuadratic : DifferentiableCost {
    double value(const double* x) override {
        if (x[0] > 2.5) return std::numeric_limits<double>::infinity();
        return std::pow(x[0] - 1.0, 2) + 3.0 * std::pow(x[1] + 2.0, 2);
    }
    double value_and_gradient(const double* x, double* g) override {
        g[0] = 2.0 * (x[0] - 1.0);
        g[1] = 6.0 * (x[1] + 2.0);
        return value(x);
    }
};

NloptSettings settings(const char* algorithm, long long evaluations) {
    NloptSettings s;
    s.algorithm = algorithm;
    s.max_evaluations = evaluations;
    s.xtol_rel = 1e-10;
    s.ftol_rel = 1e-14;
    return s;
}

bool history_consistent(const NloptSummary& s) {
    for (std::size_t k = 1; k < s.history.size(); ++k)
        if (s.history[k].best_cost > s.history[k - 1].best_cost || s.history[k].iteration <= s.history[k - 1].iteration ||
            s.history[k].evaluations < s.history[k - 1].evaluations)
            return false;
    return !s.history.empty() && s.history.front().iteration == 0 && s.history.back().best_cost == s.best_cost &&
           s.history.back().evaluations == s.evaluations;
}

}  // namespace

TEST_CASE("NLopt algorithms are found by name", "[nlopt]") {
    const auto bobyqa = find_nlopt_algorithm("LN_BOBYQA");
    REQUIRE(bobyqa);
    CHECK_FALSE(bobyqa->global);
    CHECK_FALSE(bobyqa->gradient);
    CHECK(find_nlopt_algorithm("ln_bobyqa")->name == "LN_BOBYQA");
    CHECK(find_nlopt_algorithm("NLOPT_LD_LBFGS")->gradient);
    CHECK(find_nlopt_algorithm("GN_DIRECT_L")->global);
    CHECK(find_nlopt_algorithm("G_MLSL_LDS")->needs_local);
    CHECK(find_nlopt_algorithm("GN_MLSL")->takes_local);
    CHECK_FALSE(find_nlopt_algorithm("GN_MLSL")->needs_local);
    CHECK_FALSE(find_nlopt_algorithm("LN_BOBYQAX"));
    CHECK_FALSE(find_nlopt_algorithm(""));
    const std::string list = nlopt_algorithm_list();
    for (const char* name : {"LN_BOBYQA", "LD_LBFGS", "GN_DIRECT_L", "GN_ISRES", "G_MLSL_LDS", "LN_SBPLX"})
        CHECK(list.find(name) != std::string::npos);
    CHECK(list.find("LD_LBFGS_NOCEDAL") == std::string::npos);  // not compiled into Debian's NLopt
}

TEST_CASE("NLopt local derivative-free LN_BOBYQA finds Rosenbrock's minimum", "[nlopt]") {
    Rosenbrock f;
    const NloptSummary s = run_nlopt(settings("LN_BOBYQA", 5000), {-1.2, 1.0}, {-2, -2}, {2, 2}, f);
    INFO(s.termination);
    CHECK(s.success);
    CHECK(s.algorithm == "LN_BOBYQA");
    CHECK(s.best[0] == Approx(1.0).margin(1e-5));
    CHECK(s.best[1] == Approx(1.0).margin(1e-5));
    CHECK(s.best_cost < 1e-10);
    CHECK(s.initial_cost == Approx(24.2));
    CHECK(s.gradient_evaluations == 0);
    CHECK(f.gradients == 0);
    CHECK(s.evaluations < 5000);
    CHECK(history_consistent(s));
}

TEST_CASE("NLopt local gradient-based LD_LBFGS gets the gradient and finds the minimum", "[nlopt]") {
    Rosenbrock f;
    const NloptSummary s = run_nlopt(settings("LD_LBFGS", 2000), {-1.2, 1.0}, {-1e300, -1e300}, {1e300, 1e300}, f);
    INFO(s.termination);
    CHECK(s.success);
    CHECK(s.best[0] == Approx(1.0).margin(1e-6));
    CHECK(s.best[1] == Approx(1.0).margin(1e-6));
    CHECK(s.gradient_evaluations == s.evaluations);
    CHECK(f.gradients == s.evaluations);
    CHECK(s.evaluations < 200);  // a gradient method needs far fewer evaluations than BOBYQA
    CHECK(history_consistent(s));
}

TEST_CASE("NLopt global algorithms find the global minimum among many local ones", "[nlopt]") {
    Rastrigin f;
    const std::vector<double> lo{-5.12, -5.12}, hi{5.12, 5.12}, start{3.1, -2.9};
    // A local method from (3.1, -2.9) stops in the local minimum near (3, -3).
    const NloptSummary local = run_nlopt(settings("LN_BOBYQA", 2000), start, lo, hi, f);
    CHECK(local.best_cost > 10.0);
    SECTION("deterministic DIRECT-L") {
        const NloptSummary s = run_nlopt(settings("GN_DIRECT_L", 3000), start, lo, hi, f);
        INFO(s.termination);
        CHECK(s.success);
        CHECK(std::abs(s.best[0]) < 1e-2);
        CHECK(std::abs(s.best[1]) < 1e-2);
        CHECK(s.best_cost < 1e-2);
    }
    SECTION("MLSL with a local algorithm") {
        NloptSettings ms = settings("G_MLSL_LDS", 4000);
        ms.local_algorithm = "LN_BOBYQA";
        ms.xtol_rel = 1e-8;
        const NloptSummary s = run_nlopt(ms, start, lo, hi, f);
        INFO(s.termination);
        CHECK(s.local_algorithm == "LN_BOBYQA");
        CHECK(std::abs(s.best[0]) < 1e-4);
        CHECK(std::abs(s.best[1]) < 1e-4);
        CHECK(s.best_cost < 1e-6);
    }
}

TEST_CASE("a randomized NLopt algorithm gives one result per seed", "[nlopt]") {
    Rastrigin f;
    const std::vector<double> lo{-5.12, -5.12}, hi{5.12, 5.12};
    NloptSettings s = settings("GN_CRS2_LM", 600);
    s.seed = 7;
    const NloptSummary a = run_nlopt(s, {1, 1}, lo, hi, f);
    const NloptSummary b = run_nlopt(s, {1, 1}, lo, hi, f);
    CHECK(a.best == b.best);
    CHECK(a.best_cost == b.best_cost);
    CHECK(a.evaluations == b.evaluations);
    s.seed = 8;
    const NloptSummary c = run_nlopt(s, {1, 1}, lo, hi, f);
    CHECK(c.best != a.best);
}

TEST_CASE("NLopt counts failed evaluations and keeps away from them", "[nlopt]") {
    FailingQuadratic f;
    // (Subplex takes +inf as a bad point; BOBYQA's quadratic models do not cope with it.)
    const NloptSummary s = run_nlopt(settings("LN_SBPLX", 4000), {2.0, 0.0}, {-5, -5}, {5, 5}, f);
    INFO(s.termination);
    CHECK(s.failed_evaluations > 0);
    CHECK(s.best[0] == Approx(1.0).margin(1e-5));
    CHECK(s.best[1] == Approx(-2.0).margin(1e-5));
    CHECK(std::isfinite(s.best_cost));
}

TEST_CASE("NLopt stops when the progress callback says so", "[nlopt]") {
    Rosenbrock f;
    int calls = 0;
    const NloptSummary s =
        run_nlopt(settings("LN_BOBYQA", 5000), {-1.2, 1.0}, {-2, -2}, {2, 2}, f, [&](const HistoryRow& row) {
            ++calls;
            CHECK(row.iteration == calls - 1);
            return calls < 10;
        });
    CHECK(s.termination == "stopped");
    CHECK(s.termination_type == TerminationType::stopped);
    CHECK_FALSE(s.success);
    CHECK(s.evaluations == 10);
    CHECK(std::isfinite(s.best_cost));
}

TEST_CASE("NLopt budget and bad settings", "[nlopt]") {
    Rosenbrock f;
    const NloptSummary s = run_nlopt(settings("LN_NELDERMEAD", 25), {-1.2, 1.0}, {-2, -2}, {2, 2}, f);
    CHECK(s.evaluations == 25);
    CHECK(s.termination == "evaluation limit");
    CHECK(s.termination_type == TerminationType::evaluation_limit);
    CHECK_FALSE(s.success);  // a local algorithm out of budget has not converged
    CHECK_THROWS_AS(run_nlopt(settings("LN_NOPE", 10), {0, 0}, {-1, -1}, {1, 1}, f), std::invalid_argument);
    CHECK_THROWS_AS(run_nlopt(settings("GN_DIRECT_L", 10), {0, 0}, {-1, -1e300}, {1, 1}, f), std::invalid_argument);
    CHECK_THROWS_AS(run_nlopt(settings("G_MLSL", 10), {0, 0}, {-1, -1}, {1, 1}, f), std::invalid_argument);
    NloptSettings bad_local = settings("GN_MLSL", 10);
    bad_local.local_algorithm = "GN_DIRECT";
    CHECK_THROWS_AS(run_nlopt(bad_local, {0, 0}, {-1, -1}, {1, 1}, f), std::invalid_argument);
}

}  // namespace TVID_UNITY_ID

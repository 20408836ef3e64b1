// The estimation cost as NLopt sees it: its value is IdentificationProblem::cost, and its
// gradient from the sensitivity Jacobian matches central differences of that cost, for
// the l2 cost (2 Jᵀe) and for the l1 cost (the mean-|e| subgradient per window).
#include <catch2/catch.hpp>
#include <cmath>
#include <vector>

#include "support/test_files.hpp"
#include "tvid/estimation/problem_cost.hpp"
#include "tvid/experiment/experiment.hpp"

namespace TVID_UNITY_ID {  // unique to this file in a unity build (tests/CMakeLists.txt)

using namespace tvid;
using tvid::test::source_dir;

namespace {

void check_gradient(const char* cost_kind) {
    // Two estimation windows, so the per-window weights of the l1 cost are exercised.
    const Experiment ex = load_experiment(source_dir() / "configs/cvt_tipin_clean.yaml",
                                          {{"estimation.cost", cost_kind},
                                           {"windows.estimation", "[ { time: [1.5, 2.0] }, { time: [2.2, 3.0] } ]"}});
    const IdentificationProblem problem(ex);
    ProblemCost cost(problem, EvaluatorOptions(2));
    // A point 10-20 % off the truth, inside the bounds.
    const std::vector<double> x = {1.6, 3300, 9500, 4.6, 17, 0.004, 1250, -8.0, 12.0};
    REQUIRE(x.size() == problem.dimension());
    auto ws = problem.make_workspace();
    const double reference = problem.cost(x.data(), *ws);
    CHECK(cost.value(x.data()) == Approx(reference).epsilon(1e-12));
    std::vector<double> g(x.size());
    CHECK(cost.value_and_gradient(x.data(), g.data()) == Approx(reference).epsilon(1e-12));
    for (std::size_t j = 0; j < x.size(); ++j) {
        std::vector<double> up = x, down = x;
        const double h = 1e-6 * std::abs(x[j]);
        up[j] += h;
        down[j] -= h;
        const double fd = (cost.value(up.data()) - cost.value(down.data())) / (2 * h);
        INFO(cost_kind << " parameter " << problem.free_names()[j] << ": sensitivity " << g[j] << ", differences " << fd);
        CHECK(g[j] == Approx(fd).epsilon(1e-4).margin(1e-9 * std::abs(reference) / std::abs(x[j])));
    }
    CHECK(cost.simulations() > 0);
}

}  // namespace

TEST_CASE("the l2 cost's gradient 2 J^T e matches differences", "[nlopt][cost]") { check_gradient("l2"); }

TEST_CASE("the l1 cost's subgradient matches differences", "[nlopt][cost]") { check_gradient("l1"); }

}  // namespace TVID_UNITY_ID

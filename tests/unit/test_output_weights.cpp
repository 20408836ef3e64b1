// Several outputs in one cost: each output's residual is multiplied by its weight over its
// measured spread in the estimation windows (normalize: spread, the default with several
// outputs), or by its weight alone (normalize: none, the default with one output).
#include <catch2/catch.hpp>
#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "support/test_files.hpp"
#include "tvid/estimation/problem_cost.hpp"
#include "tvid/estimation/residual_filter.hpp"
#include "tvid/experiment/experiment.hpp"

namespace TVID_UNITY_ID {  // unique to this file in a unity build (tests/CMakeLists.txt)

using namespace tvid;
using tvid::test::source_dir;

namespace {

// The standard deviation of a·i + b over i = first … last, by hand: |a|·√((n² − 1)/12).
double arithmetic_spread(double a, int first, int last) {
    const double n = last - first + 1;
    return std::abs(a) * std::sqrt((n * n - 1) / 12);
}

const char* kTwoOutputs = R"(tvid: 1
name: two-outputs
data: { file: rec.csv, time: t }
model:
  nodes: [ { name: motor, J: 0.1 }, { name: load, J: 0.2 } ]
  elements:
    - { type: torque, name: drive, node: motor, input: T_in }
    - { type: spring_damper, name: shaft, between: [motor, load], k: k_s, c: 0.5 }
    - { type: friction, name: bearing, node: load, c: 0.3 }
inputs: { T_in: u }
outputs:
  w_load:  { column: w, speed: load }
  T_shaft: { column: T, torque: shaft, weight: 3 }
parameters:
  k_s: { init: 100, min: 1, max: 1000 }
windows: { estimation: [ { samples: [10, 50] } ] }
initial_state: rest
)";

Experiment two_outputs(const std::vector<Override>& overrides = {}) {
    static test::TempDir dir;
    std::string csv = "t,u,w,T\n";
    for (int i = 0; i <= 100; ++i)  // w = 2i, T = 1 + i
        csv += std::to_string(i * 1e-3) + "," + std::to_string(0.5 * i) + "," + std::to_string(2 * i) + "," +
               std::to_string(1 + i) + "\n";
    dir.write("rec.csv", csv);
    return load_experiment(dir.write("two.yaml", kTwoOutputs), overrides);
}

}  // namespace

TEST_CASE("each output's factor is its weight over its spread in the estimation windows", "[estimation][weights]") {
    // Samples 10 … 50: 10 is the initial state, 11 … 50 are scored.
    const double spread_w = arithmetic_spread(2, 11, 50), spread_T = arithmetic_spread(1, 11, 50);
    SECTION("several outputs: normalized by default") {
        const ProblemDefinition d = problem_definition(two_outputs());
        CHECK(d.normalized);
        REQUIRE(d.output_spread.size() == 2);
        CHECK(d.output_spread[0] == Approx(spread_w).epsilon(1e-12));
        CHECK(d.output_spread[1] == Approx(spread_T).epsilon(1e-12));
        CHECK(d.output_scale[0] == Approx(1.0 / spread_w).epsilon(1e-12));
        CHECK(d.output_scale[1] == Approx(3.0 / spread_T).epsilon(1e-12));
    }
    SECTION("normalize: none keeps raw units, times the weight") {
        const ProblemDefinition d = problem_definition(two_outputs({parse_override("estimation.normalize=none")}));
        CHECK_FALSE(d.normalized);
        CHECK(d.output_scale == std::vector<double>{1.0, 3.0});
    }
    SECTION("one output: not normalized unless asked") {
        const Experiment one = load_experiment(source_dir() / "configs/cvt_tipin.yaml");
        CHECK_FALSE(problem_definition(one).normalized);
        CHECK(problem_definition(one).output_scale == std::vector<double>{1.0});
        const Experiment asked =
            load_experiment(source_dir() / "configs/cvt_tipin.yaml", {parse_override("estimation.normalize=spread")});
        const ProblemDefinition d = problem_definition(asked);
        CHECK(d.normalized);
        CHECK(d.output_scale[0] == Approx(1.0 / d.output_spread[0]).epsilon(1e-15));
    }
}

TEST_CASE("the normalized cost is the sum of the scaled residuals, and its gradient follows", "[estimation][weights]") {
    // The measured bench: a torque in the 1/12 shaft (spread 3 N m) and one in the
    // coupling (0.36 N m), a speed source and a steady start.
    const Experiment ex = load_experiment(source_dir() / "configs/aalto_bench.yaml",
                                          {parse_override("windows.estimation=[ { samples: [0, 1500] } ]")});
    const IdentificationProblem problem(ex);
    const ProblemDefinition& d = problem.definition();
    REQUIRE(d.normalized);
    auto ws = problem.make_workspace();
    const std::vector<double>& x = problem.initial();
    std::vector<double> params;
    problem.full_parameters(x.data(), params);
    const WindowTrace tr = problem.trace(params, ex.estimation[0], *ws);
    REQUIRE(tr.status == SimulationStatus::ok);
    double by_hand = 0.0;
    for (std::size_t k = 0; k < 2; ++k)
        for (std::size_t i = 0; i < tr.samples.size(); ++i) {
            const double e = d.output_scale[k] * (tr.simulated[k][i] - tr.measured[k][i]);
            by_hand += e * e;
        }
    CHECK(problem.cost(x.data(), *ws) == Approx(by_hand).epsilon(1e-12));
    // Its gradient from the scaled sensitivity rows matches central differences.
    ProblemCost cost(problem, EvaluatorOptions(1));
    std::vector<double> g(x.size());
    CHECK(cost.value_and_gradient(x.data(), g.data()) == Approx(by_hand).epsilon(1e-12));
    for (std::size_t j = 0; j < x.size(); ++j) {
        std::vector<double> up = x, down = x;
        // Steps of 1e-4: the angles are thousands of radians (the encoder's cumulative
        // angle), so a twist is known to about 1e-12 rad.
        // A phase may start at 0; a delay (d_T, from 0) steps by a thousandth of a sample.
        const double h = problem.free_names()[j] == "d_T" ? 1e-6 : x[j] != 0 ? 1e-4 * std::abs(x[j]) : 1e-4;
        up[j] += h;
        down[j] -= h;
        const double fd = (cost.value(up.data()) - cost.value(down.data())) / (2 * h);
        INFO("parameter " << problem.free_names()[j] << ": sensitivity " << g[j] << ", differences " << fd);
        CHECK(g[j] == Approx(fd).epsilon(1e-3));
    }
}

TEST_CASE("a detrended and high-passed output is scored filtered, in the cost and in its gradient", "[estimation][weights]") {
    const Experiment ex = load_experiment(source_dir() / "configs/aalto_bench.yaml",
                                          {parse_override("windows.estimation=[ { samples: [0, 1500] } ]"),
                                           parse_override("outputs.torque_upper.highpass=5"),
                                           parse_override("outputs.torque_lower.detrend=linear")});
    REQUIRE(ex.outputs[0].scoring.highpass == 5.0);
    REQUIRE(ex.outputs[1].scoring.detrend == Detrend::linear);
    const IdentificationProblem problem(ex);
    const ProblemDefinition& d = problem.definition();
    REQUIRE(d.filtered);
    auto ws = problem.make_workspace();
    const std::vector<double>& x = problem.initial();
    std::vector<double> params;
    problem.full_parameters(x.data(), params);
    const WindowTrace tr = problem.trace(params, ex.estimation[0], *ws);
    REQUIRE(tr.status == SimulationStatus::ok);
    double by_hand = 0.0;
    for (std::size_t k = 0; k < 2; ++k) {
        std::vector<double> e(tr.samples.size());
        for (std::size_t i = 0; i < e.size(); ++i) e[i] = d.output_scale[k] * (tr.simulated[k][i] - tr.measured[k][i]);
        filter_residuals(d.output_filter[k], tr.time.data(), e.data(), e.size(), 1);
        for (double v : e) by_hand += v * v;
    }
    CHECK(problem.cost(x.data(), *ws) == Approx(by_hand).epsilon(1e-12));
    ProblemCost cost(problem, EvaluatorOptions(1));
    CHECK(cost.value(x.data()) == Approx(by_hand).epsilon(1e-12));
    std::vector<double> g(x.size());
    cost.value_and_gradient(x.data(), g.data());
    // A parameter that moves mostly the mean (a loss) has a small gradient once the mean is
    // removed: compared on the scale of the largest component.
    double largest = 0.0;
    for (double v : g) largest = std::max(largest, std::abs(v));
    for (std::size_t j = 0; j < x.size(); ++j) {
        std::vector<double> up = x, down = x;
        const double h = problem.free_names()[j] == "d_T" ? 1e-6 : x[j] != 0 ? 1e-4 * std::abs(x[j]) : 1e-4;
        up[j] += h;
        down[j] -= h;
        const double fd = (cost.value(up.data()) - cost.value(down.data())) / (2 * h);
        INFO("parameter " << problem.free_names()[j] << ": sensitivity " << g[j] << ", differences " << fd);
        CHECK(g[j] == Approx(fd).epsilon(1e-3).margin(1e-5 * largest));
    }
}

}  // namespace TVID_UNITY_ID

// The profile likelihood (fit/profile_likelihood.hpp): for a model linear in its parameters
// Δχ² is the exact parabola (v − θ̂)²/se², and its 95 % interval θ̂ ± 1.96 se; the
// profile is the same for any thread count.
#include <catch2/catch.hpp>
#include <cmath>
#include <random>
#include <string>

#include "support/test_files.hpp"
#include "tvid/experiment/experiment.hpp"
#include "tvid/fit/profile_likelihood.hpp"
#include "tvid/report/parameter_file.hpp"
#include "tvid/util/input_error.hpp"

namespace TVID_UNITY_ID {  // unique to this file in a unity build (tests/CMakeLists.txt)

using namespace tvid;

namespace {

// y = a·u + b through a torque element's torque with an output gain and offset: linear in
// (a, b), with white noise on y.
Experiment linear_experiment(test::TempDir& dir, const std::string& extra = "") {
    std::mt19937 random(5);
    std::normal_distribution<double> gauss(0.0, 0.1);
    std::string csv = "t,u,y\n";
    char line[96];
    for (int i = 0; i <= 1000; ++i) {
        const double t = i * 1e-3;
        const double u = std::sin(2 * 3.141592653589793 * 3 * t) + 0.5 * std::cos(2 * 3.141592653589793 * 7 * t);
        std::snprintf(line, sizeof line, "%.6f,%.17g,%.17g\n", t, u, 2.0 * u + 0.3 + gauss(random));
        csv += line;
    }
    dir.write("lin.csv", csv);
    return load_experiment(dir.write("lin.yaml", R"(tvid: 1
name: linear
data: { file: lin.csv, time: t }
model:
  nodes: [ { name: hub, J: 1.0 } ]
  elements:
    - { type: torque, name: drive, node: hub, input: T_in }
    - { type: friction, name: bearing, node: hub, c: 1.0 }
inputs: { T_in: u }
outputs:
  y: { column: y, torque: drive, gain: a, offset: b }
parameters:
  a: { init: 1, min: -10, max: 10 }
  b: { init: 0, min: -10, max: 10 }
windows: { estimation: [ { samples: [0, 1000] } ] }
initial_state: rest
estimation: { optimizer: lm, cost: l2, lm: { stol: 0 } }   # each inner fit to its tolerance: the exact parabola
)" + extra));
}

}  // namespace

TEST_CASE("the profile of a linear problem is the exact parabola", "[profile]") {
    test::TempDir dir;
    const Experiment ex = linear_experiment(dir);
    ProfileOptions options;
    options.parameter = "a";
    options.points = 9;
    options.threads = 1;
    const ProfileResult p = profile_likelihood(ex, initial_parameters(ex), options);
    REQUIRE(p.points.size() == 9);
    REQUIRE(std::isfinite(p.std_error));
    CHECK(p.best_value == Approx(2.0).epsilon(0.01));
    CHECK(p.residuals == 1000);
    CHECK(p.s2 == Approx(p.best_cost / (1000 - 2)).epsilon(1e-12));
    // From θ̂ − 4 se to θ̂ + 4 se.
    CHECK(p.points.front().value == Approx(p.best_value - 4 * p.std_error).epsilon(1e-12));
    CHECK(p.points.back().value == Approx(p.best_value + 4 * p.std_error).epsilon(1e-12));
    for (const ProfilePoint& q : p.points) {
        INFO(q.value);
        const double z = (q.value - p.best_value) / p.std_error;
        CHECK(q.delta_chi2 == Approx(z * z).margin(1e-6));
        CHECK(q.converged);
        REQUIRE(q.others.size() == 1);
    }
    REQUIRE(p.low);
    REQUIRE(p.high);
    CHECK(*p.low == Approx(p.best_value - std::sqrt(kProfileThreshold95) * p.std_error).epsilon(1e-9));
    CHECK(*p.high == Approx(p.best_value + std::sqrt(kProfileThreshold95) * p.std_error).epsilon(1e-9));
    CHECK_FALSE(p.better_point_found);

    SECTION("the same on two threads") {
        options.threads = 2;
        const ProfileResult q = profile_likelihood(ex, initial_parameters(ex), options);
        for (std::size_t k = 0; k < p.points.size(); ++k) CHECK(q.points[k].cost == p.points[k].cost);
    }
    SECTION("a grid that never reaches the threshold leaves the interval open") {
        options.from = p.best_value - p.std_error;
        options.to = p.best_value + p.std_error;
        const ProfileResult q = profile_likelihood(ex, initial_parameters(ex), options);
        CHECK_FALSE(q.low);
        CHECK_FALSE(q.high);
    }
}

TEST_CASE("profile input errors name what is wrong", "[profile]") {
    test::TempDir dir;
    ProfileOptions options;
    options.parameter = "c";
    const Experiment ex = linear_experiment(dir);
    CHECK_THROWS_AS(profile_likelihood(ex, initial_parameters(ex), options), InputError);
    options.parameter = "a";
    options.from = -20.0;
    CHECK_THROWS_WITH(profile_likelihood(ex, initial_parameters(ex), options), Catch::Contains("beyond the parameter's bounds"));
    const Experiment l1 = load_experiment(dir.path() / "lin.yaml", {parse_override("estimation.cost=l1"),
                                                                    parse_override("estimation.optimizer=pso")});
    options.from.reset();
    CHECK_THROWS_WITH(profile_likelihood(l1, initial_parameters(l1), options), Catch::Contains("set cost: l2"));
}

}  // namespace TVID_UNITY_ID

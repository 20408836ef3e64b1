// Identifiability at the optimum: rank, relative standard errors and flags, correlated
// pairs, and null directions written as parameter combinations. On the CVT preset the
// nine parameters have the exact scaling symmetry of Yoshida & Takamatsu eqs. 15–21 (θ → sθ with
// ρ1 → sρ1, μ → sμ, k± → k±/s, c± → c±/s, σ → σ/s leaves Tds unchanged).
#include <catch2/catch.hpp>
#include <algorithm>
#include <cmath>
#include <limits>
#include <nlohmann/json.hpp>

#include "support/test_files.hpp"
#include "tvid/analysis/identifiability.hpp"
#include "tvid/experiment/experiment.hpp"

namespace TVID_UNITY_ID {  // unique to this file in a unity build (tests/CMakeLists.txt)

using namespace tvid;

namespace {

std::vector<double> unit(std::vector<double> v) {
    double n = 0;
    for (double x : v) n += x * x;
    for (double& x : v) x /= std::sqrt(n);
    return v;
}

// The CVT tip-in experiment on the noise-free recording with every parameter's init at
// the truth; `overrides` fix some of them.
Experiment cvt_at_truth(std::vector<Override> overrides = {}) {
    const auto truth = nlohmann::json::parse(test::read_text(test::source_dir() / "data/cvt/truth.json"))["parameters"];
    for (auto it = truth.begin(); it != truth.end(); ++it) {
        char value[64];
        std::snprintf(value, sizeof value, "%.17g", it.value().get<double>());
        bool fixed = false;
        for (const Override& o : overrides) fixed = fixed || o.key == "parameters." + it.key();
        if (!fixed) overrides.push_back({"parameters." + it.key() + ".init", value});
    }
    return load_experiment(test::source_dir() / "configs/cvt_tipin_clean.yaml", overrides);
}

}  // namespace

TEST_CASE("a null direction with equal and opposite components reads as a scaling by s and 1/s", "[identifiability]") {
    const ParameterCombination c =
        describe_null_direction(unit({1, -1, 0.001, -1}), {"a", "b", "c", "d"}, {2.0, 3.0, 4.0, 5.0});
    CHECK(c.members == std::vector<std::string>{"a", "b", "d"});
    CHECK(c.exponents == std::vector<double>{1, -1, 0, -1});
    CHECK(c.multiplicative);
    CHECK(c.text == "scaling a by s and b and d by 1/s leaves the output unchanged");
}

TEST_CASE("exponents near small fractions are rounded, others printed as numbers", "[identifiability]") {
    // Relative to the leading component a: b moves half as much, c two thirds against it.
    const auto c = describe_null_direction(unit({0.9, 0.45, -0.6}), {"a", "b", "c"}, {1.0, 1.0, 1.0});
    CHECK(c.exponents[1] == 0.5);
    CHECK(c.exponents[2] == Approx(-2.0 / 3.0).epsilon(1e-15));
    CHECK(c.text == "scaling a by s, b by s^(1/2) and c by 1/s^(2/3) leaves the output unchanged");
    // The leading component is the first of at least half the largest: here b, so a gets s^0.37.
    const auto d = describe_null_direction(unit({0.37, 1.0, 2.0}), {"a", "b", "c"}, {1.0, 1.0, 1.0});
    CHECK(d.exponents[0] == Approx(0.37));
    CHECK(d.exponents[2] == 2.0);
    CHECK(d.text == "scaling a by s^0.37, b by s and c by s^2 leaves the output unchanged");
}

TEST_CASE("a direction along one parameter says it has no effect, a zero value changes by an amount", "[identifiability]") {
    CHECK(describe_null_direction({0.0, 1.0, 0.01}, {"J1", "C1", "C2"}, {1, 1, 1}).text ==
          "C1 has no effect on the output");
    // d_ds at 0 has no relative change: δd_ds = t·v (column scale 1), ln d_tm changes by −t·v.
    const auto c = describe_null_direction(unit({1, -1}), {"d_ds", "d_tm"}, {0.0, 3.0});
    CHECK_FALSE(c.multiplicative);
    CHECK(c.text == "scaling d_tm by s while changing d_ds by -1·ln(s) (absolute changes) leaves the output unchanged");
}

TEST_CASE("start corrections in a null direction change by amounts, never scale", "[identifiability][start]") {
    // Two speed corrections of an estimated start, each at its coordinate's scale (50 rad/s):
    // additive corrections that start at 0, whatever their value at the optimum.
    const std::vector<ParameterScaleRule> rules = {{50, "its coordinate's scale (50)"}, {50, "its coordinate's scale (50)"}};
    const auto c = describe_null_direction(unit({1, -1}), {"start1.flywheel.speed", "start1.load.speed"}, {0.3, -0.2},
                                           rules, {50, 50});
    CHECK_FALSE(c.multiplicative);
    CHECK(c.members == std::vector<std::string>{"start1.flywheel.speed", "start1.load.speed"});
    CHECK(c.text == "changing start1.flywheel.speed by +0.71 and start1.load.speed by -0.71 together "
                    "(absolute changes, or any multiple of them) leaves the output unchanged");
    // The components are in units of each column's scale: the amounts take it back.
    const auto d = describe_null_direction(unit({1, -1}), {"start1.a.speed", "start1.b.speed"}, {0.3, -0.2}, rules,
                                           {50, 100});
    CHECK(d.text == "changing start1.a.speed by +0.45 and start1.b.speed by -0.89 together "
                    "(absolute changes, or any multiple of them) leaves the output unchanged");
    // A delay (its rule: a sample period) is shifted too.
    const auto e = describe_null_direction(unit({1, 1}), {"delay_T", "start1.b.speed"}, {2e-3, 0.1},
                                           {{1e-3, "a sample period (0.001 s)"}, rules[0]}, {2e-3, 50});
    CHECK(e.text.rfind("changing delay_T by +4e-05 and start1.b.speed by +1 together", 0) == 0);
}

TEST_CASE("a null direction mixing physical parameters and a start correction reads per member", "[identifiability][start]") {
    // ln k and ln J rise with ln s; the load's start speed moves by 10 rad/s per unit of ln s.
    const std::vector<ParameterScaleRule> rules = {{}, {}, {20, "its coordinate's scale (20)"}};
    const auto c = describe_null_direction(unit({1, 1, 0.5}), {"k", "J", "start1.load.speed"}, {1e4, 0.5, 0.1}, rules,
                                           {1e4, 0.5, 20});
    CHECK_FALSE(c.multiplicative);
    CHECK(c.exponents == std::vector<double>{1, 1, 0});
    CHECK(c.text == "scaling k and J by s while changing start1.load.speed by +10·ln(s) (absolute changes) "
                    "leaves the output unchanged");
    // Through assess_identifiability: the rules and the uncertainty's column scales reach it.
    ParameterUncertainty u;
    u.available = true;
    u.rank = 2;
    u.condition_number = std::numeric_limits<double>::infinity();
    const double nan = std::numeric_limits<double>::quiet_NaN();
    u.std_error = {nan, nan, nan};
    u.determined = {false, false, false};
    u.correlation.assign(3, std::vector<double>(3, nan));
    u.null_directions = {unit({1, 1, 0.5})};
    u.column_scale = {1e4, 0.5, 20};
    const auto r = assess_identifiability(u, {"k", "J", "start1.load.speed"}, {1e4, 0.5, 0.1}, rules);
    REQUIRE(r.null_directions.size() == 1);
    CHECK(r.null_directions[0].text == c.text);
    CHECK(r.warning().find("scaling start1") == std::string::npos);
}

TEST_CASE("relative standard errors, weak flags and strongly correlated pairs", "[identifiability]") {
    const double nan = std::numeric_limits<double>::quiet_NaN();
    ParameterUncertainty u;
    u.available = true;
    u.rank = 4;
    u.condition_number = 1e7;
    u.std_error = {0.1, 6.0, 0.5, 0.2};
    u.determined = {true, true, true, true};
    u.correlation = {{1, 0.2, -0.97, 0}, {0.2, 1, 0.1, 0.9}, {-0.97, 0.1, 1, 0}, {0, 0.9, 0, 1}};
    const auto r = assess_identifiability(u, {"J1", "J2", "C1", "C2"}, {1.0, -10.0, 0.99, 0.0});
    REQUIRE(r.parameters.size() == 4);
    CHECK(r.parameters[0].relative_std_error == Approx(0.1));
    CHECK(r.parameters[0].flag == IdentifiabilityFlag::ok);
    CHECK(r.parameters[1].relative_std_error == Approx(0.6));  // |value|
    CHECK(r.parameters[1].flag == IdentifiabilityFlag::weak);
    CHECK(r.parameters[2].flag == IdentifiabilityFlag::weak);   // 50.5 %
    CHECK(std::isnan(r.parameters[3].relative_std_error));     // value 0: no relative error
    CHECK(r.parameters[3].flag == IdentifiabilityFlag::ok);
    REQUIRE(r.correlated_pairs.size() == 1);  // 0.9 itself is not above the threshold
    CHECK(r.correlated_pairs[0].first == "J1");
    CHECK(r.correlated_pairs[0].second == "C1");
    CHECK(r.correlated_pairs[0].correlation == -0.97);
    CHECK(r.warning() == "weakly determined (relative std error > 50 %): J2 60 %, C1 50.5 %");

    u.std_error = {0.1, 1.0, 0.1, 0.2};
    CHECK(assess_identifiability(u, {"J1", "J2", "C1", "C2"}, {1.0, -10.0, 0.99, 0.0}).warning().empty());
    u.std_error[1] = nan;
    u.determined[1] = false;
    u.rank = 3;
    u.null_directions = {{0, 1, 0, 0}};
    const auto d = assess_identifiability(u, {"J1", "J2", "C1", "C2"}, {1.0, -10.0, 0.99, 0.0});
    CHECK(d.parameters[1].flag == IdentifiabilityFlag::undetermined);
    CHECK(d.warning() == "the data determine only 3 of 4 parameter directions: J2 has no effect on the output "
                         "(fix one of these parameters)");
}

TEST_CASE("CVT with all nine parameters free: rank 8 and the scaling symmetry named", "[identifiability][cvt]") {
    const Experiment ex = cvt_at_truth();
    const IdentificationProblem problem(ex);
    REQUIRE(problem.dimension() == 9);
    const std::vector<double> at = problem.initial();
    const ParameterUncertainty u = estimate_uncertainty(problem, at);
    REQUIRE(u.available);
    const IdentifiabilityReport r = assess_identifiability(u, problem.free_names(), at);
    CHECK(r.rank == 8);
    CHECK(r.of == 9);
    CHECK(std::isinf(r.condition_number));
    REQUIRE(r.null_directions.size() == 1);
    // rho1 k_minus k_plus c_minus c_plus mu sigma d_ds d_tm: ln ρ1 and ln μ rise with ln s,
    // the stiffnesses, dampings and σ fall with it, the offsets do not take part.
    const std::vector<double> expected = unit({1, -1, -1, -1, -1, 1, -1, 0, 0});
    const auto& v = r.null_directions[0].vector;
    for (std::size_t j = 0; j < 9; ++j) {
        INFO(problem.free_names()[j]);
        CHECK(v[j] == Approx(expected[j]).margin(1e-3));
    }
    CHECK(r.null_directions[0].exponents == std::vector<double>{1, -1, -1, -1, -1, 1, -1, 0, 0});
    CHECK(r.null_directions[0].text ==
          "scaling rho1 and mu by s and k_minus, k_plus, c_minus, c_plus and sigma by 1/s leaves the output unchanged");
    for (const auto& p : r.parameters) {
        INFO(p.name);
        const bool offset = p.name == "d_ds" || p.name == "d_tm";
        CHECK(p.flag == (offset ? IdentifiabilityFlag::ok : IdentifiabilityFlag::undetermined));
    }
    CHECK(r.warning().find("only 8 of 9") != std::string::npos);
    CHECK(r.warning().find("rho1 and mu by s") != std::string::npos);
}

TEST_CASE("CVT with rho1 fixed: the other eight parameters are identifiable", "[identifiability][cvt]") {
    const auto truth = nlohmann::json::parse(test::read_text(test::source_dir() / "data/cvt/truth.json"))["parameters"];
    char rho1[64];
    std::snprintf(rho1, sizeof rho1, "%.17g", truth["rho1"].get<double>());
    const Experiment ex = cvt_at_truth({{"parameters.rho1", rho1}});
    const IdentificationProblem problem(ex);
    REQUIRE(problem.dimension() == 8);
    const std::vector<double> at = problem.initial();
    const IdentifiabilityReport r =
        assess_identifiability(estimate_uncertainty(problem, at), problem.free_names(), at);
    REQUIRE(r.available);
    CHECK(r.rank == 8);
    CHECK(r.of == 8);
    CHECK(std::isfinite(r.condition_number));
    CHECK(r.null_directions.empty());
    for (const auto& p : r.parameters) {
        INFO(p.name);
        CHECK(p.flag != IdentifiabilityFlag::undetermined);
        CHECK(std::isfinite(p.std_error));
    }
    CHECK(r.warning().find("parameter directions") == std::string::npos);
}

TEST_CASE("a delay, offset or phase near 0 is judged against its natural scale, not its value", "[identifiability]") {
    // A delay of 5 µs ± 12.5 µs at 1 kHz: 250 % of its value, 1.25 % of a sample period.
    ParameterUncertainty u;
    u.available = true;
    u.rank = 2;
    u.condition_number = 10;
    u.std_error = {1.25e-5, 1.25e-5};
    u.determined = {true, true};
    u.correlation = {{1, 0}, {0, 1}};
    const std::vector<ParameterScaleRule> rules = {{1e-3, "a sample period (0.001 s)"}, {}};
    const auto r = assess_identifiability(u, {"d", "c"}, {5e-6, 5e-6}, rules);
    REQUIRE(r.parameters.size() == 2);
    CHECK(r.parameters[0].relative_std_error == Approx(2.5));
    CHECK(r.parameters[0].judged_std_error == Approx(0.0125));
    CHECK(r.parameters[0].judged_against == "a sample period (0.001 s)");
    CHECK(r.parameters[0].flag == IdentifiabilityFlag::ok);
    CHECK(r.parameters[1].flag == IdentifiabilityFlag::weak);  // an ordinary parameter: relative
    CHECK(r.warning() == "weakly determined (relative std error > 50 %): c 250 %");
    // A delay well away from 0 is judged by its value again: 3 ms ± 2 ms is weak.
    u.std_error = {2e-3, 1e-7};
    const auto far = assess_identifiability(u, {"d", "c"}, {3e-3, 5e-6}, rules);
    CHECK(far.parameters[0].judged_against == "its value");
    CHECK(far.parameters[0].flag == IdentifiabilityFlag::weak);
}

TEST_CASE("a free line seen only through its shaft torque: its start speeds change together by equal amounts",
          "[identifiability][start]") {
    // No loss to ground and only the shaft's torque measured: every node's start speed raised
    // by the same amount turns the whole line faster and leaves every twist, so the torque, as
    // it was. Each correction's column is at its own coordinate's scale; the amounts are equal.
    const test::TempDir dir;
    const std::string data = (test::source_dir() / "data/free_line/free_line_clean.csv").string();
    const auto file = dir.write("line.yaml", "tvid: 1\n"
                                             "data: { file: '" + data + "', time: t }\n"
                                             "model:\n"
                                             "  nodes: [ { name: engine, J: 0.25 }, { name: gearbox, J: 0.06 }, { name: vehicle, J: J_v } ]\n"
                                             "  elements:\n"
                                             "    - { type: torque, name: drive, node: engine, input: T_engine }\n"
                                             "    - { type: spring_damper, name: clutch, between: [engine, gearbox], k: 600, c: 1.5 }\n"
                                             "    - { type: spring_damper, name: shaft, between: [gearbox, vehicle], k: 4000, c: 6 }\n"
                                             "inputs: { T_engine: T_engine }\n"
                                             "outputs: { T_shaft: { column: T_shaft, torque: shaft } }\n"
                                             "parameters: { J_v: { init: 9, min: 0.1, max: 1000 } }\n"
                                             "windows: { estimation: [ { time: [0, 2] } ] }\n"
                                             "initial_state: { kind: estimated, from: rest }\n"
                                             "simulation: { method: rk4, step: 1.0e-3 }\n"
                                             "estimation: { cost: l2, optimizer: lm }\n");
    const Experiment ex = load_experiment(file);
    const IdentificationProblem problem(ex);
    // At corrections away from 0, where a relative reading would speak of scaling them.
    std::vector<double> at = problem.initial();
    double correction = 0.3;
    for (std::size_t j = 0; j < at.size(); ++j)
        if (problem.start_scale(j) > 0) at[j] = correction -= 0.2;
    const ParameterUncertainty u = estimate_uncertainty(problem, at);
    REQUIRE(u.available);
    REQUIRE(u.column_scale.size() == problem.dimension());
    for (std::size_t j = 0; j < problem.dimension(); ++j) {
        INFO(problem.free_names()[j]);
        const double s = problem.start_scale(j);
        CHECK(u.column_scale[j] == (s > 0 ? std::max(std::abs(at[j]), s) : std::abs(at[j])));
    }
    const IdentifiabilityReport r = assess_identifiability(problem, u, at);
    REQUIRE(r.null_directions.size() == 1);
    const ParameterCombination& c = r.null_directions[0];
    INFO(c.text);
    CHECK(c.members == std::vector<std::string>{"start1.engine.speed", "start1.gearbox.speed", "start1.vehicle.speed"});
    CHECK_FALSE(c.multiplicative);
    CHECK(c.text == "changing start1.engine.speed by +0.58, start1.gearbox.speed by +0.58 and start1.vehicle.speed by "
                    "+0.58 together (absolute changes, or any multiple of them) leaves the output unchanged");
}

}  // namespace TVID_UNITY_ID

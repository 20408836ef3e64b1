// initial_state: { kind: estimated }: which start coordinates become parameters (every
// node's speed, every angle but the one of a rotation nothing sees), that they are seeded by
// the recipe, that their sensitivity columns are exact on both fixed-step paths, that a
// validation window fits its own start on its first samples, and the refusals. On the free
// line of configs/free_line_clean.yaml (data by scripts/generate_free_line_data.py).
#include <catch2/catch.hpp>
#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <optional>
#include <string>
#include <vector>

#include "support/test_files.hpp"
#include "tvid/estimation/forward_sensitivity.hpp"
#include "tvid/experiment/estimated_start.hpp"
#include "tvid/experiment/experiment.hpp"
#include "tvid/model/parameter_units.hpp"
#include "tvid/util/input_error.hpp"

namespace TVID_UNITY_ID {  // unique to this file in a unity build (tests/CMakeLists.txt)

using namespace tvid;
using tvid::test::source_dir;

namespace {

Experiment free_line(const std::vector<Override>& overrides = {}) {
    return load_experiment(source_dir() / "configs/free_line_clean.yaml", overrides);
}

std::vector<std::string> start_names(const Experiment& ex) {
    std::vector<std::string> names;
    for (const NetworkSpec::StartCoordinate& c : ex.network.start_coordinates)
        names.push_back(ex.network.parameter_names[static_cast<std::size_t>(c.parameter)]);
    return names;
}

std::string refusal(const std::vector<Override>& overrides, const char* config = "configs/free_line_clean.yaml") {
    try {
        const Experiment ex = load_experiment(source_dir() / config, overrides);
        const IdentificationProblem problem(ex);
    } catch (const InputError& e) {
        return e.what();
    }
    return "";
}

// The truth of data/free_line/truth.json as the problem's free vector: the model's
// parameters, and each start correction as the true start less the seed.
std::vector<double> truth(const IdentificationProblem& problem) {
    const std::vector<std::pair<const char*, double>> values{
        {"J_e", 0.25},  {"J_g", 0.06},  {"J_v", 9.0},   {"k_cl", 600.0}, {"c_cl", 1.5},
        {"k_ds", 4000}, {"c_ds", 6.0},  {"c_v", 0.9},   {"start1.gearbox.angle", -0.085},
        {"start1.vehicle.angle", -0.12}, {"start1.engine.speed", 31.0}, {"start1.gearbox.speed", 29.5},
        {"start1.vehicle.speed", 30.0}};
    std::vector<double> x(problem.dimension(), 0.0);
    for (std::size_t j = 0; j < x.size(); ++j)
        for (const auto& [name, v] : values)
            if (problem.free_names()[j] == name) x[j] = v;
    // A start's parameter is its correction to the seed (the measured start: untwisted at the
    // first measured engine speed, which on the clean recording is the true 31 rad/s).
    for (const NetworkSpec::StartCoordinate& c : problem.definition().network.start_coordinates) {
        const long j = problem.free_column(c.parameter);
        x[static_cast<std::size_t>(j)] -= problem.definition().estimated.seed[c.window][c.state];
    }
    return x;
}

}  // namespace

TEST_CASE("an estimated start on a line not tied to ground: every speed and every twist, each seeded at 0",
          "[estimated_start]") {
    const Experiment ex = free_line();
    CHECK(start_names(ex) == std::vector<std::string>{"start1.gearbox.angle", "start1.vehicle.angle",
                                                      "start1.engine.speed", "start1.gearbox.speed",
                                                      "start1.vehicle.speed"});
    const std::vector<std::string> units = parameter_units(ex.network);
    CHECK(units[static_cast<std::size_t>(ex.network.parameter_index("start1.vehicle.angle"))] == "rad");
    CHECK(units[static_cast<std::size_t>(ex.network.parameter_index("start1.vehicle.speed"))] == "rad/s");
    const IdentificationProblem problem(ex);
    REQUIRE(problem.dimension() == 13);
    for (std::size_t j = 8; j < 13; ++j) CHECK(problem.initial()[j] == 0.0);
    // The measured recipe: untwisted, every node at the first measured engine speed.
    const std::vector<double>& seed = problem.definition().estimated.seed.at(0);
    const double first_speed = ex.data.column("w_engine").front();
    CHECK(seed == std::vector<double>{0, 0, 0, first_speed, first_speed, first_speed});
    // The engine's angle is the seed's: the whole line turned is the same line.
    CHECK(ex.network.parameter_index("start1.engine.angle") < 0);
}

TEST_CASE("a start speed's search box is 10 % of the largest speed its node turns at, in its unit", "[estimated_start]") {
    const Experiment ex = free_line();
    const auto range_of = [&](const std::string& name) {
        const int i = ex.network.parameter_index(name);
        REQUIRE(i >= 0);
        REQUIRE(ex.parameters[static_cast<std::size_t>(i)].range);
        return ex.parameters[static_cast<std::size_t>(i)].range->second;
    };
    const auto largest = [&](const char* column) {
        double l = 0.0;
        for (double v : ex.data.column(column)) l = std::max(l, std::abs(v));
        return l;
    };
    // The shafts tie the three nodes into one steady rotation (ratio 1): each turns at up to
    // the faster of the two measured speeds, and the gearbox, measured by nothing, as well.
    const double fastest = std::max(largest("w_engine"), largest("w_vehicle"));
    REQUIRE(largest("w_engine") != Approx(largest("w_vehicle")));
    for (const char* speed : {"start1.engine.speed", "start1.gearbox.speed", "start1.vehicle.speed"})
        CHECK(range_of(speed) == Approx(kStartSpeedShare * fastest));
    CHECK(range_of("start1.vehicle.angle") == kStartAngleRange);
}

TEST_CASE("a spring to ground makes every angle a start coordinate, each estimation window has its own",
          "[estimated_start]") {
    const Experiment held = free_line(
        {{"model.elements",
          "[{type: torque, name: drive, node: engine, input: T_engine},"
          " {type: spring_damper, name: clutch_damper, between: [engine, gearbox], k: k_cl, c: c_cl},"
          " {type: spring_damper, name: driveshaft, between: [gearbox, vehicle], k: k_ds, c: c_ds},"
          " {type: spring_damper, name: mount, between: [vehicle, ground], k: 50},"
          " {type: friction, name: rolling, node: vehicle, c: c_v}]"}});
    CHECK(held.network.parameter_index("start1.engine.angle") >= 0);
    CHECK(held.network.start_coordinates.size() == 6);
    const Experiment two = free_line({{"windows.estimation", "[{time: [0, 3]}, {time: [4, 7]}]"}});
    CHECK(two.network.start_coordinates.size() == 10);
    CHECK(two.network.parameter_index("start2.vehicle.speed") >= 0);
}

TEST_CASE("an estimated start's sensitivity columns equal central differences on both fixed-step paths",
          "[estimated_start][sensitivity]") {
    const Experiment ex = free_line({{"windows.estimation", "[{time: [0, 1]}]"}});
    const IdentificationProblem problem(ex);
    // Off the truth, with every correction away from 0.
    std::vector<double> x = problem.initial();
    const std::vector<double> corrections{-0.05, -0.1, 0.3, -1.2, -0.7};
    for (std::size_t j = 0; j < corrections.size(); ++j) x[8 + j] = corrections[j];
    auto ws = problem.make_workspace();
    std::vector<double> up, down;
    REQUIRE(problem.residuals(x.data(), *ws, up));
    const auto rows = static_cast<Eigen::Index>(up.size()), cols = static_cast<Eigen::Index>(x.size());
    Eigen::MatrixXd fd(rows, cols);
    for (std::size_t j = 0; j < x.size(); ++j) {
        // The outputs are linear in a start coordinate (a linear line): a wide step leaves
        // no truncation and keeps the rounding of the angles' difference (~1e-11) small.
        const double h = (problem.start_scale(j) > 0 ? 1e-2 : 1e-5) * std::max(std::abs(x[j]), 1.0);
        std::vector<double> p = x;
        p[j] = x[j] + h;
        REQUIRE(problem.residuals(p.data(), *ws, up));
        p[j] = x[j] - h;
        REQUIRE(problem.residuals(p.data(), *ws, down));
        for (Eigen::Index i = 0; i < rows; ++i)
            fd(i, static_cast<Eigen::Index>(j)) = (up[static_cast<std::size_t>(i)] - down[static_cast<std::size_t>(i)]) / (2 * h);
    }
    ForwardSensitivity sensitivity(problem);
    auto sws = sensitivity.make_workspace();
    Eigen::MatrixXd packed(rows, cols), augmented(rows, cols);
    REQUIRE(sensitivity.jacobian_columns(x.data(), 0, x.size(), *sws, packed));
    sensitivity.set_packed(false);
    REQUIRE(sensitivity.jacobian_columns(x.data(), 0, x.size(), *sws, augmented));
    for (Eigen::Index j = 0; j < cols; ++j) {
        INFO(problem.free_names()[static_cast<std::size_t>(j)]);
        CHECK((packed.col(j) - fd.col(j)).norm() < 1e-6 * fd.col(j).norm());
        CHECK((packed.col(j) - augmented.col(j)).norm() <= 1e-9 * augmented.col(j).norm());
    }
}

TEST_CASE("the truth's start gives the noise-free recording, a validation window fits its own start",
          "[estimated_start]") {
    const Experiment ex = free_line();
    const IdentificationProblem problem(ex);
    const std::vector<double> x = truth(problem);
    auto ws = problem.make_workspace();
    std::vector<double> r;
    REQUIRE(problem.residuals(x.data(), *ws, r));
    double largest = 0.0;
    for (const double v : r) largest = std::max(largest, std::abs(v));
    CHECK(largest < 1e-6);  // the recording's own RK4 and tvid's agree to this
    // The validation window (8 to 12 s) estimates its start on its first tenth: at the true
    // parameters its outputs follow the recording; from the recipe (untwisted) they ring.
    const std::vector<double> params = problem.full_parameters(x);
    const auto worst = [&](const IdentificationProblem& p) {
        auto w = p.make_workspace();
        const WindowTrace t = p.trace(params, p.experiment().validation.at(0), *w);
        REQUIRE(t.status == SimulationStatus::ok);
        double e = 0.0;
        for (std::size_t k = 0; k < t.measured.size(); ++k)
            for (std::size_t i = 0; i < t.measured[k].size(); ++i)
                e = std::max(e, std::abs(t.simulated[k][i] - t.measured[k][i]));
        return e;
    };
    CHECK(worst(problem) < 1e-5);
    const Experiment from_recipe = free_line({{"initial_state.validation", "from"}});
    const IdentificationProblem recipe_problem(from_recipe);
    CHECK(worst(recipe_problem) > 1.0);
}

TEST_CASE("estimated starts refuse what they cannot seed or estimate, naming initial_state",
          "[estimated_start]") {
    CHECK_THAT(refusal({{"initial_state", "{kind: estimated}"}}),
               Catch::Contains("initial_state.from") && Catch::Contains("steady, measured, equilibrium or rest"));
    CHECK_THAT(refusal({{"initial_state", "estimated"}}), Catch::Contains("from: steady | measured"));
    // Nothing holds the line: the equilibrium has no seed.
    CHECK_THAT(refusal({{"initial_state.from", "equilibrium"}}),
               Catch::Contains("free_line_clean.yaml:") && Catch::Contains("initial_state") &&
                   Catch::Contains("cannot be computed at the parameters' init"));
    CHECK_THAT(refusal({{"initial_state", "{kind: estimated, from: measured}"}}, "configs/engine_idle_clean.yaml"),
               Catch::Contains("crank-angle channel"));
    CHECK_THAT(refusal({{"initial_state.validation", "sometimes"}}), Catch::Contains("initial_state.validation"));
}

}  // namespace TVID_UNITY_ID

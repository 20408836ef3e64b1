// The elements of real drivetrains, fitted by `tvid fit` on recordings made by independent
// numpy scripts (scripts/generate_NAME_data.py, each with its own RK4): dry friction with
// a Stribeck rise and each direction its own, a road load, a clutch damper of two spring
// stages with friction hysteresis, a lossy gear, a positioning drive under its PD position
// controller, and one under a digital PID (1 kHz, one sample's delay, limits), a vehicle launch through a rigid
// lossy gearbox, and a vehicle driveline whose clutch damper's hysteresis sticks and slips (estimated on one
// recording, validated on another). The noise-free recordings give every parameter back; the noisy ones reach
// their noise floor with the truth within its errors.
// The inverse-model set-up (a speed source at the measured speed) gives with dry friction
// as an element the parameters an exact sign column gives.
#include <catch2/catch.hpp>
#include <nlohmann/json.hpp>
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <map>
#include <string>
#include <utility>
#include <vector>

#include "support/run_tvid.hpp"
#include "support/shipped_fit.hpp"
#include "support/test_files.hpp"

namespace TVID_UNITY_ID {  // unique to this file in a unity build (tests/CMakeLists.txt)

using namespace tvid::test;
using nlohmann::json;

namespace {

json truth_of(const std::string& recording) {
    return json::parse(read_text(source_dir() / "data" / recording / "truth.json"));
}

std::map<std::string, json> parameters_of(const json& summary) {
    std::map<std::string, json> out;
    for (const json& p : summary["parameters"]) out[p["name"].get<std::string>()] = p;
    return out;
}

}  // namespace

TEST_CASE("each new element's noise-free recording gives every parameter back", "[e2e][element_fits]") {
    const TempDir tmp;
    for (const std::string recording : {"dry_friction", "road_load", "clutch_damper", "lossy_gear", "positioning_drive",
                                      "digital_drive", "rigid_gear", "driveline"}) {
        INFO(recording);
        const json s = fit_shipped(tmp, recording + "_clean");
        CHECK(s["optimizer"]["converged"] == true);
        const json truth = truth_of(recording)["parameters"];
        const auto fitted = parameters_of(s);
        CHECK(fitted.size() == truth.size());
        for (auto it = truth.begin(); it != truth.end(); ++it) {
            INFO(it.key() << " = " << fitted.at(it.key())["value"] << ", truth " << it.value());
            CHECK(fitted.at(it.key())["value"].get<double>() == Approx(it.value().get<double>()).epsilon(1e-6));
        }
    }
}

TEST_CASE("each new element's noisy recording: the noise floor, the truth within its errors", "[e2e][element_fits]") {
    const TempDir tmp;
    for (const std::string recording : {"dry_friction", "road_load", "clutch_damper", "lossy_gear", "positioning_drive",
                                      "digital_drive", "rigid_gear", "driveline"}) {
        INFO(recording);
        const json s = fit_shipped(tmp, recording);
        const json t = truth_of(recording);
        // Validation over time the fit never saw: at the sensors' noise.
        const json& v = s["validation"]["pooled"];
        for (auto it = t["noise_std"].begin(); it != t["noise_std"].end(); ++it) {
            INFO(it.key() << ": validation RMSE " << v[it.key()]["rmse"] << ", noise " << it.value());
            CHECK(v[it.key()]["rmse"].get<double>() < 1.1 * it.value().get<double>());
        }
        for (const auto& [name, p] : parameters_of(s)) {
            const double value = p["value"].get<double>(), se = p["std_error"].get<double>();
            const double truth = t["parameters"][name].get<double>();
            INFO(name << " = " << value << " ± " << se << ", truth " << truth);
            CHECK(std::abs(value - truth) < 4.0 * se);
        }
        CHECK(s["verdict"]["errors"] == 0);
    }
}

TEST_CASE("inverse model: dry friction as an element gives the exact sign column's parameters within 1 %",
          "[e2e][element_fits]") {
    const TempDir tmp;
    const auto element = parameters_of(fit_shipped(tmp, "inverse_friction"));
    const auto sign = parameters_of(fit_shipped(tmp, "inverse_friction_sign"));
    for (const std::string name : {"J", "c", "Fc"}) {
        const double a = element.at(name)["value"].get<double>(), b = sign.at(name)["value"].get<double>();
        INFO(name << ": element " << a << ", sign column " << b);
        CHECK(std::abs(a - b) < 0.01 * std::abs(b));
    }
}

TEST_CASE("the new elements' units reach the report", "[e2e][element_fits]") {
    const TempDir tmp;
    const auto friction = parameters_of(fit_shipped(tmp, "dry_friction_clean"));
    CHECK(friction.at("coulomb")["unit"] == "N m");
    CHECK(friction.at("stribeck_speed")["unit"] == "rad/s");
    CHECK(friction.at("c_negative")["unit"] == "N m s/rad");
    const auto damper = parameters_of(fit_shipped(tmp, "clutch_damper_clean"));
    CHECK(damper.at("k2")["unit"] == "N m/rad");
    CHECK(damper.at("theta1")["unit"] == "rad");
    CHECK(damper.at("Fh")["unit"] == "N m");
    const auto road = parameters_of(fit_shipped(tmp, "road_load_clean"));
    CHECK(road.at("c_air")["unit"] == "N m s^2/rad^2");
    const auto gear = parameters_of(fit_shipped(tmp, "lossy_gear_clean"));
    CHECK(gear.at("eta")["unit"] == "1");
}

TEST_CASE("a new element's bad entry is one line naming the file, line and key, exit 2", "[e2e][elements]") {
    const TempDir tmp;
    std::filesystem::create_directories(tmp.path() / "data");
    const auto variant = [&](const std::string& config, const std::string& from, const std::string& to) {
        std::string text = read_text(source_dir() / "configs" / (config + ".yaml"));
        REQUIRE(text.find(from) != std::string::npos);
        text.replace(text.find(from), from.size(), to);
        const auto file = tmp.write("configs/variant.yaml", text);
        return run_tvid({"simulate", file.string(), "-o", (tmp.path() / "simulated.csv").string()});
    };
    struct Case {
        std::string config, from, to, key, says;
    };
    const Case cases[] = {
        {"dry_friction", "coulomb: coulomb, coulomb_negative: coulomb_negative, breakaway: breakaway,",
         "coulomb: 5, coulomb_negative: coulomb_negative, breakaway: 1,", "breakaway", "must be at least coulomb"},
        {"dry_friction", "name: bearing, node: shaft,", "name: bearing, node: shaft, between: [shaft],", "between",
         "not both"},
        {"dry_friction", "stribeck_speed: stribeck_speed,", "", "breakaway", "needs both breakaway"},
        {"clutch_damper", "{ angle: theta1, k: k2 }", "{ angle: theta1, stiffness: k2 }", "stages[1].stiffness",
         "unknown key 'stiffness'"},
        {"clutch_damper", "stages: [", "stages_negative: 3, stages: [", "stages_negative", "expected a list"},
        {"lossy_gear", "efficiency: eta", "efficiency: 1.5", "efficiency", "must be at most 1"},
        {"road_load", "smoothing_speed: 0.1", "smoothing_speed: -1", "smoothing_speed", "must be positive"},
        {"positioning_drive", "kp: kp, kd: kd", "kp: kp, ki: -5, kd: kd", "ki", "cannot be negative"},
        {"digital_drive", "delay: 0.001", "delay: 0.0015", "delay", "expected a whole number of sample periods"},
        {"digital_drive", "sample_period: 0.001, delay: 0.001", "sample_period: 0.0015, delay: 0.003", "sample_period",
         "is not a whole number of sample intervals"},
        {"digital_drive", "angle_average: 2", "angle_average: 0", "angle_average", "expected a whole number"},
        {"rigid_gear", "torque: halfshaft", "torque: gearbox", "torque", "offers no torque output"},
        {"rigid_gear", "    - { type: spring_damper, name: halfshaft,",
         "    - { type: ideal_gear, name: back, between: [gear_out, gear_in], ratio: 0.25 }\n"
         "    - { type: spring_damper, name: halfshaft,",
         "between", "ideal gears around a loop"},
        {"rigid_gear", "efficiency: eta }", "efficiency: 1.2 }", "efficiency", "must be at most 1"},
    };
    for (const Case& c : cases) {
        const std::string data = "data/" + c.config;
        if (!std::filesystem::exists(tmp.path() / data))
            std::filesystem::copy(source_dir() / data, tmp.path() / data);
        const RunResult r = variant(c.config, c.from, c.to);
        INFO(c.config << ": " << c.to << "\n" << r.err);
        CHECK(r.exit_code == 2);
        CHECK(r.err.find("variant.yaml:") != std::string::npos);
        CHECK(r.err.find(c.key + ":") != std::string::npos);
        CHECK(r.err.find(c.says) != std::string::npos);
        CHECK(std::count(r.err.begin(), r.err.end(), '\n') == 1);
    }
}

TEST_CASE("a rule between an element's fields holds for its parameters' bounds", "[e2e][elements]") {
    // The rules a constant keeps (limits that hold zero, stages in order, an efficiency of at
    // most 1, a breakaway torque at least the Coulomb one) are kept by a parameter's bounds:
    // a rule on one field for every value of them, an order for some.
    const TempDir tmp;
    std::filesystem::create_directories(tmp.path() / "data");
    const auto variant = [&](const std::string& config, const std::vector<std::pair<std::string, std::string>>& edits) {
        const std::string data = "data/" + config;
        if (!std::filesystem::exists(tmp.path() / data)) std::filesystem::copy(source_dir() / data, tmp.path() / data);
        std::string text = read_text(source_dir() / "configs" / (config + ".yaml"));
        for (const auto& [from, to] : edits) {
            REQUIRE(text.find(from) != std::string::npos);
            text.replace(text.find(from), from.size(), to);
        }
        const auto file = tmp.write("configs/variant.yaml", text);
        return run_tvid({"simulate", file.string(), "-o", (tmp.path() / "simulated.csv").string()});
    };
    struct Case {
        std::string config;
        std::vector<std::pair<std::string, std::string>> edits;
        std::string key, says;  ///< key empty: accepted
    };
    const std::string fc = "  Fc: { init: 0.105,  min: 0,      max: 2 }";
    const Case cases[] = {
        {"digital_drive", {{"limits: [-0.9, 0.9]", "limits: [L, 0.6]"}, {fc, fc + "\n  L: { init: 0.2, min: 0.1, max: 2 }"}},
         "parameters.L", "element 'drive': limits: expected [min, max] with min <= 0 <= max and min < max, got [L (bounds [0.1, 2]), 0.6]"},
        {"digital_drive", {{"limits: [-0.9, 0.9]", "limits: [L, L]"}, {fc, fc + "\n  L: { init: -0.5, min: -1, max: 0 }"}},
         "parameters.L", "limits: expected [min, max]"},
        {"digital_drive", {{"limits: [-0.9, 0.9]", "limits: [L, 0.6]"}, {fc, fc + "\n  L: { init: -0.5, min: -2, max: 0 }"}},
         "", ""},
        {"clutch_damper",
         {{"{ angle: theta1, k: k2 } ]", "{ angle: theta1, k: k2 }, { angle: theta0, k: k2 } ]"},
          {"  theta1: { init: 0.039, min: 0.001, max: 0.5 }",
           "  theta1: { init: 0.039, min: 0.001, max: 0.5 }\n  theta0: { init: 0.0005, min: 0.0001, max: 0.001 }"}},
         "parameters.theta0", "stages: the stage angles must rise from zero outwards: stage 3's theta0 (bounds [0.0001, 0.001]) rad cannot lie beyond stage 2's theta1"},
        {"lossy_gear", {{"eta: { init: 0.63,  min: 0.5,    max: 1.0 }", "eta: { init: 0.63,  min: 0.5,    max: 1.2 }"}},
         "parameters.eta", "efficiency: must be at most 1 (got eta (bounds [0.5, 1.2]))"},
        {"dry_friction",
         {{"coulomb:          { init: 1.4,   min: 0,    max: 10 }", "coulomb:          { init: 3,   min: 2,    max: 10 }"},
          {"breakaway:        { init: 5.2,   min: 0,    max: 10 }", "breakaway:        { init: 1,   min: 0,    max: 1.5 }"}},
         "parameters.breakaway", "breakaway: must be at least coulomb (coulomb (bounds [2, 10]) N m)"},
    };
    for (const Case& c : cases) {
        const RunResult r = variant(c.config, c.edits);
        INFO(c.config << ": " << c.edits.front().second << "\n" << r.err);
        if (c.key.empty()) {
            CHECK(r.exit_code == 0);
            continue;
        }
        CHECK(r.exit_code == 2);
        CHECK(r.err.find("variant.yaml:") != std::string::npos);
        CHECK(r.err.find(c.key + ": its bounds break a rule of element") != std::string::npos);
        CHECK(r.err.find(c.says) != std::string::npos);
        CHECK(std::count(r.err.begin(), r.err.end(), '\n') == 1);
    }
}

TEST_CASE("a sampled controller whose clock misses every sample of the recording is refused at its key",
          "[e2e][elements][sampled_controller]") {
    const TempDir tmp;
    // Samples at t = 0.0005 + k·0.001: none falls on the controller's 1 ms clock.
    std::string csv = "t,theta_ref,theta,T_drive\n";
    for (int k = 0; k < 50; ++k) csv += std::to_string(0.0005 + 0.001 * k) + ",0,0,0\n";
    std::filesystem::create_directories(tmp.path() / "data" / "digital_drive");
    std::filesystem::create_directories(tmp.path() / "configs");
    tmp.write("data/digital_drive/digital_drive.csv", csv);
    const auto config = tmp.write("configs/digital_drive.yaml", read_text(source_dir() / "configs/digital_drive.yaml"));
    const RunResult r = run_tvid({"simulate", config.string(), "-o", (tmp.path() / "simulated.csv").string()});
    INFO(r.err);
    CHECK(r.exit_code == 2);
    CHECK(r.err.find("digital_drive.yaml:20: model.elements[0].sample_period: no sample of") != std::string::npos);
    CHECK(std::count(r.err.begin(), r.err.end(), '\n') == 1);
    CHECK_FALSE(std::filesystem::exists(tmp.path() / "simulated.csv"));
}

TEST_CASE("a continuous PI position controller integrates in its own node and refuses an equilibrium start",
          "[e2e][elements]") {
    const TempDir tmp;
    std::filesystem::create_directories(tmp.path() / "configs");
    std::filesystem::create_directories(tmp.path() / "data");
    std::filesystem::copy(source_dir() / "data" / "positioning_drive", tmp.path() / "data" / "positioning_drive");
    std::string text = read_text(source_dir() / "configs" / "positioning_drive.yaml");
    const auto swap = [&](const std::string& from, const std::string& to) {
        REQUIRE(text.find(from) != std::string::npos);
        text.replace(text.find(from), from.size(), to);
    };
    swap("kp: kp, kd: kd }", "kp: kp, ki: 3, kd: kd }");
    const auto pi = tmp.write("configs/pi.yaml", text);
    const RunResult ok = run_tvid({"simulate", pi.string(), "-o", (tmp.path() / "pi.csv").string()});
    INFO(ok.err);
    REQUIRE(ok.exit_code == 0);
    CHECK(read_text(tmp.path() / "pi.csv").find("theta") != std::string::npos);
    swap("initial_state: rest", "initial_state: equilibrium");
    const auto at_equilibrium = tmp.write("configs/pi_equilibrium.yaml", text);
    const RunResult r = run_tvid({"simulate", at_equilibrium.string(), "-o", (tmp.path() / "eq.csv").string()});
    INFO(r.err);
    CHECK(r.exit_code == 2);
    CHECK(r.err.find("pi_equilibrium.yaml:") != std::string::npos);
    CHECK(r.err.find("initial_state: node servo.integral holds a position controller's integral") != std::string::npos);
    CHECK(std::count(r.err.begin(), r.err.end(), '\n') == 1);
}

}  // namespace TVID_UNITY_ID

// A gear mesh's ratio n joins θa − n·θb: a ratio of 0 joins nothing, and its angles come
// out NaN. Through the binary, a ratio of 0, or a ratio parameter whose bounds reach 0, is
// refused at load: exit status 2 and one line "FILE:LINE: key: what is wrong".
#include <catch2/catch.hpp>
#include <cmath>
#include <string>

#include "support/run_tvid.hpp"
#include "support/test_files.hpp"

namespace TVID_UNITY_ID {  // unique to this file in a unity build (tests/CMakeLists.txt)

using namespace tvid::test;

namespace {

// A two-node gear train; `ratio` is the mesh's ratio (a number or the parameter n) and
// `n` the parameter's entry (empty: no parameter n).
std::string gear_train(const std::string& ratio, const std::string& n) {
    return "tvid: 1\n"                                                                        // 1
           "name: gear-ratio\n"                                                               // 2
           "data: { file: '" + (source_dir() / "data/cvt/tipin_clean.csv").string() + "', time: t }\n"  // 3
           "model:\n"                                                                         // 4
           "  nodes:\n"                                                                       // 5
           "    - { name: a, J: 0.1 }\n"                                                      // 6
           "    - { name: b, J: 0.5 }\n"                                                      // 7
           "  elements:\n"                                                                    // 8
           "    - { type: torque, name: drive, node: a, input: T_drive }\n"                   // 9
           "    - { type: gear_mesh, name: stage, between: [a, b], ratio: " + ratio + ", k: 1000, c: 5 }\n"  // 10
           "    - { type: friction, name: bearing, node: b, c: 0.5 }\n"                       // 11
           "inputs: { T_drive: Ttm }\n"                                                       // 12
           "outputs:\n"                                                                       // 13
           "  T_mesh: { column: Tds, torque: stage }\n"                                       // 14
           + (n.empty() ? std::string("parameters: {}\n") : "parameters:\n  n: " + n + "\n") +  // 15-16
           "windows:\n"
           "  estimation: [ { samples: [0, 200] } ]\n"
           "initial_state: rest\n"
           "simulation: { method: rk4, step: sample }\n";
}

std::size_t line_count(const std::string& text) {
    std::size_t n = 0;
    for (char c : text) n += c == '\n';
    return n;
}

bool contains(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

RunResult simulate(TempDir& tmp, const std::string& experiment) {
    const auto exp = tmp.write("gear.yaml", experiment);
    return run_tvid({"simulate", exp.string(), "-o", (tmp.path() / "sim.csv").string()});
}

}  // namespace

TEST_CASE("a gear mesh with ratio 0 is refused at load", "[e2e][network]") {
    TempDir tmp;
    const RunResult r = simulate(tmp, gear_train("0", ""));
    INFO("stderr: " << r.err);
    CHECK(r.exit_code == 2);
    CHECK(line_count(r.err) == 1);
    CHECK(contains(r.err, "gear.yaml:10:"));
    CHECK(contains(r.err, "model.elements[1].ratio: must not be zero: a gear ratio (got 0)"));
    CHECK_FALSE(std::filesystem::exists(tmp.path() / "sim.csv"));
}

TEST_CASE("a gear ratio parameter's bounds may not reach 0", "[e2e][network]") {
    struct Case {
        const char* entry;
        const char* key;
    };
    for (const Case c : {Case{"{ init: 2, min: -1, max: 5 }", "parameters.n.min"},   // straddles 0
                         Case{"{ init: 2, min: 0, max: 5 }", "parameters.n.min"},    // touches 0
                         Case{"{ init: -2, min: -5, max: 0 }", "parameters.n.min"},  // touches 0 from below
                         Case{"{ init: 2 }", "parameters.n:"}}) {                    // unbounded: reaches 0
        SECTION(c.entry) {
            TempDir tmp;
            const RunResult r = simulate(tmp, gear_train("n", c.entry));
            INFO("stderr: " << r.err);
            CHECK(r.exit_code == 2);
            CHECK(line_count(r.err) == 1);
            CHECK(contains(r.err, c.key));
            CHECK(contains(r.err, "reach 0: n is a gear ratio, which must not be zero"));
        }
    }
    SECTION("a fixed ratio of 0 as a parameter") {
        TempDir tmp;
        const RunResult r = simulate(tmp, gear_train("n", "{ value: 0 }"));
        INFO("stderr: " << r.err);
        CHECK(r.exit_code == 2);
        CHECK(line_count(r.err) == 1);
        CHECK(contains(r.err, "parameters.n.value: must not be zero: n is a gear ratio (got 0)"));
    }
    SECTION("bounds on one side of 0 are accepted") {
        TempDir tmp;
        const RunResult r = simulate(tmp, gear_train("n", "{ init: 3, min: 1, max: 5 }"));
        INFO("stderr: " << r.err);
        CHECK(r.exit_code == 0);
    }
}

TEST_CASE("a node behind a 160:1 gear may turn 160 times faster than the measured one: the divergence guard "
          "goes through the ratio",
          "[e2e][network]") {
    TempDir tmp;
    // A motor (J 1e-3) drives a load (J 0.5, viscous 2) through 160:1; a constant 0.05 N m
    // takes the load towards 160·0.05/2 = 4 rad/s with the time constant of the inertia
    // seen at the load, (0.5 + 160²·1e-3)/2 = 13.05 s. Only the load's speed is recorded:
    // in 2 s it reaches 0.57 rad/s while the motor turns at 91 rad/s, beyond 100 times the
    // load's largest speed but well within 100 times it through the ratio.
    std::string csv = "t,T,w_load\n";
    for (int i = 0; i <= 2000; ++i) {
        const double t = i * 1e-3;
        csv += std::to_string(t) + ",0.05," + std::to_string(4.0 * (1.0 - std::exp(-t / 13.05))) + "\n";
    }
    const auto data = tmp.write("geared.csv", csv);
    const auto exp = tmp.write("geared.yaml",
                               "tvid: 1\n"
                               "name: geared\n"
                               "data: { file: '" + data.string() + "', time: t }\n"
                               "model:\n"
                               "  nodes:\n"
                               "    - { name: motor, J: 1.0e-3 }\n"
                               "    - { name: load, J: 0.5 }\n"
                               "  elements:\n"
                               "    - { type: torque, name: drive, node: motor, input: T }\n"
                               "    - { type: gear_mesh, name: head, between: [motor, load], ratio: 160, k: 1000, c: 5 }\n"
                               "    - { type: friction, name: loss, node: load, c: c }\n"
                               "inputs: { T: T }\n"
                               "outputs: { w_load: { column: w_load, speed: load } }\n"
                               "parameters: { c: { init: 2, min: 0.1, max: 10 } }\n"
                               "windows: { estimation: [ { time: [0, 2] } ] }\n"
                               "initial_state: rest\n"
                               "simulation: { method: rk4, step: 1.0e-4 }\n");
    const RunResult r = run_tvid({"simulate", exp.string(), "--json"});
    INFO(r.err);
    CHECK(r.exit_code == 0);
    CHECK(r.err.find("diverged") == std::string::npos);
    // The load's speed follows the recording (to the gear's compliance).
    const auto rmse_at = r.out.find("\"rmse\"");
    REQUIRE(rmse_at != std::string::npos);
    CHECK(std::stod(r.out.substr(r.out.find(':', rmse_at) + 1)) < 0.05);
}

}  // namespace TVID_UNITY_ID

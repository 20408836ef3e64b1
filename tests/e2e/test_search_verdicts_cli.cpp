// A global search on a line not tied to ground (the constant-load recording of
// scripts/generate_constant_load_data.py, its box a decade each side of the truth, log
// scale): the swarm alone ends far from the optimum and the verdict says its best is no
// minimum; from the swarm's best, least squares reaches the optimum and the verdict is
// quiet about it.
#include <catch2/catch.hpp>
#include <nlohmann/json.hpp>
#include <string>

#include "support/run_tvid.hpp"
#include "support/test_files.hpp"

namespace TVID_UNITY_ID {  // unique to this file in a unity build (tests/CMakeLists.txt)

using namespace tvid::test;
using nlohmann::json;

namespace {

std::string wide_box_experiment() {
    const std::string data = (source_dir() / "data/constant_load/constant_load.csv").string();
    return R"(tvid: 1
name: constant-load-wide
data: { file: )" + data + R"(, time: t }
model:
  nodes: [ { name: motor, J: J1 }, { name: load, J: J2 } ]
  elements:
    - { type: torque, name: drive, node: motor, input: T_motor }
    - { type: spring_damper, name: shaft, between: [motor, load], k: k, c: c }
    - { type: friction, name: bearing, node: load, c: c2 }
    - { type: torque, name: brake, node: load, value: T_load }
inputs: { T_motor: T_motor }
outputs:
  w2: { column: w2, speed: load }
  T_shaft: { column: T_shaft, torque: shaft }
parameters:
  J1:     { init: 0.05, min: 0.005, max: 0.5, scale: log }
  J2:     { init: 0.2, min: 0.02, max: 2.0, scale: log }
  k:      { init: 800, min: 80, max: 8000, scale: log }
  c:      { init: 1.5, min: 0.15, max: 15, scale: log }
  c2:     { init: 0.08, min: 0.008, max: 0.8, scale: log }
  T_load: { init: -12, min: -120, max: 0 }
windows:
  estimation: [ { time: [0, 2.5] } ]
  validation: [ { time: [2.5, 4] } ]
initial_state: rest
simulation: { method: rk4, step: 1.0e-4 }
estimation:
  cost: l2
  optimizer: pso
  pso: { start: latin_hypercube, particles: 32, iterations: 40, seed: 3 }
)";
}

json fit(const TempDir& tmp, const std::string& name, std::vector<std::string> extra) {
    const auto config = tmp.write(name + ".yaml", wide_box_experiment());
    std::vector<std::string> args{"fit", config.string(), "-o", (tmp.path() / name).string(), "--threads", "2", "--json"};
    args.insert(args.end(), extra.begin(), extra.end());
    const RunResult r = run_tvid(args);
    INFO(r.err);
    REQUIRE(r.exit_code == 0);
    return json::parse(r.out);
}

bool has_finding(const json& summary, const std::string& code) {
    for (const json& f : summary["verdict"]["findings"])
        if (f["code"] == code) return true;
    return false;
}

}  // namespace

TEST_CASE("a swarm whose best is no minimum is told so, least squares from it reaches the optimum",
          "[e2e][verdict]") {
    const TempDir tmp;
    const json swarm = fit(tmp, "swarm", {});
    const json polished = fit(tmp, "polished", {"--optimizer", "pso+lm"});
    const double optimum = polished["cost"]["value"].get<double>();
    INFO("swarm cost " << swarm["cost"]["value"] << ", pso+lm cost " << optimum);
    // The optimum of this recording: the noise floor (LM from init reaches 2.853).
    CHECK(optimum == Approx(2.853).epsilon(0.01));
    CHECK(swarm["cost"]["value"].get<double>() > 1.5 * optimum);
    CHECK(has_finding(swarm, "not_at_minimum"));
    CHECK_FALSE(has_finding(polished, "not_at_minimum"));
}

}  // namespace TVID_UNITY_ID

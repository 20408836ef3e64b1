// Units of parameters and outputs (model/parameter_units.hpp): a preset's from its
// catalogue, a custom network's from the field each parameter fills.
#include <catch2/catch.hpp>
#include <string>
#include <vector>

#include "support/test_files.hpp"
#include "tvid/experiment/experiment.hpp"
#include "tvid/model/parameter_units.hpp"

using namespace tvid;

TEST_CASE("a custom network's parameter units follow the fields they fill", "[model][units]") {
    test::TempDir dir;
    std::string csv = "t,u,w,T\n";
    for (int i = 0; i <= 20; ++i) csv += std::to_string(i * 1e-3) + ",1,0,0\n";
    dir.write("rec.csv", csv);
    const Experiment ex = load_experiment(dir.write("units.yaml", R"(tvid: 1
name: units
data: { file: rec.csv, time: t }
model:
  nodes: [ { name: motor, J: J_m }, { name: load, J: 0.2 } ]
  elements:
    - { type: torque, name: drive, node: motor, input: T_in }
    - { type: spring_damper, name: shaft, between: [motor, load], k: k_s, c: c_s }
    - { type: friction, name: bearing, node: load, c: c_b }
inputs: { T_in: u }
outputs:
  w_load:  { column: w, speed: load }
  T_shaft: { column: T, torque: shaft, offset: d_T }
parameters:
  J_m: { init: 0.1, min: 0.01, max: 1 }
  k_s: { init: 100, min: 1, max: 1000 }
  c_s: { init: 0.5, min: 0, max: 10 }
  c_b: { init: 0.3, min: 0, max: 10 }
  d_T: { init: 0, min: -5, max: 5 }
windows: { estimation: [ { samples: [0, 20] } ] }
initial_state: rest
)"));
    const std::vector<std::string> units = parameter_units(ex.network);
    REQUIRE(ex.network.parameter_names == std::vector<std::string>{"J_m", "k_s", "c_s", "c_b", "d_T"});
    CHECK(units == std::vector<std::string>{"kg m^2", "N m/rad", "N m s/rad", "N m s/rad", "N m"});
    CHECK(std::string(output_unit(ex.network.outputs[static_cast<std::size_t>(ex.output_indices[0])])) == "rad/s");
    CHECK(std::string(output_unit(ex.network.outputs[static_cast<std::size_t>(ex.output_indices[1])])) == "N m");
}

TEST_CASE("a preset's parameter units are its catalogue's", "[model][units]") {
    const Experiment ex = load_experiment(test::source_dir() / "configs/engine_idle.yaml");
    const std::vector<std::string> units = parameter_units(ex.network);
    REQUIRE(units.size() == 10);
    CHECK(units[0] == "kg m^2");  // J1
    CHECK(units[3] == "kg");      // m
    CHECK(units[7] == "N m s/rad");  // C21
}

// Units of parameters and outputs (model/parameter_units.hpp): a preset's from its
// catalogue, a custom network's from the field each parameter fills.
#include <catch2/catch.hpp>
#include <string>
#include <vector>

#include "support/test_files.hpp"
#include "tvid/experiment/experiment.hpp"
#include "tvid/model/parameter_units.hpp"

namespace TVID_UNITY_ID {  // unique to this file in a unity build (tests/CMakeLists.txt)

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
    CHECK(output_unit(ex.network, ex.network.outputs[static_cast<std::size_t>(ex.output_indices[0])]) == "rad/s");
    CHECK(output_unit(ex.network, ex.network.outputs[static_cast<std::size_t>(ex.output_indices[1])]) == "N m");
}

TEST_CASE("a preset's parameter units are its catalogue's", "[model][units]") {
    const Experiment ex = load_experiment(test::source_dir() / "configs/engine_idle.yaml");
    const std::vector<std::string> units = parameter_units(ex.network);
    REQUIRE(units.size() == 10);
    CHECK(units[0] == "kg m^2");  // J1
    CHECK(units[3] == "kg");      // m
    CHECK(units[7] == "N m s/rad");  // C21
}

TEST_CASE("a linear analogue reports metres, newtons and kilograms", "[model][units]") {
    test::TempDir dir;
    std::string csv = "t,F,x,v\n";
    for (int i = 0; i <= 20; ++i) csv += std::to_string(i * 1e-3) + ",1,0,0\n";
    dir.write("rec.csv", csv);
    // A cart (mass m) on a spring to ground, with viscous and Coulomb friction, pushed by a
    // measured force; a shaft on the same model stays rotational.
    const Experiment ex = load_experiment(dir.write("linear.yaml", R"(tvid: 1
name: linear
data: { file: rec.csv, time: t }
model:
  nodes: [ { name: cart, J: m, motion: linear }, { name: shaft, J: J_s } ]
  elements:
    - { type: torque, name: push, node: cart, input: F_in }
    - { type: spring_damper, name: mount, between: [cart], k: k_m, c: c_m }
    - { type: friction, name: rail, node: cart, c: c_r, coulomb: F_c }
    - { type: spring_damper, name: coupling, between: [shaft], k: k_s }
inputs: { F_in: { column: F, unit: kN } }
outputs:
  x:       { column: x, unit: mm, angle: cart }
  v:       { column: v, speed: cart, offset: v0 }
  F_mount: { column: F, torque: mount }
  w_shaft: { column: v, speed: shaft }
parameters:
  m:   { init: 2, min: 0.1, max: 10 }
  J_s: { init: 0.1, min: 0.01, max: 1 }
  k_m: { init: 100, min: 1, max: 1000 }
  c_m: { init: 0.5, min: 0, max: 10 }
  c_r: { init: 0.3, min: 0, max: 10 }
  F_c: { init: 1, min: 0, max: 10 }
  k_s: { init: 50, min: 1, max: 1000 }
  v0:  { init: 0, min: -1, max: 1 }
windows: { estimation: [ { samples: [0, 20] } ] }
initial_state: rest
)"));
    const std::vector<std::string> units = parameter_units(ex.network);
    const auto unit_of = [&](const std::string& name) {
        return units[static_cast<std::size_t>(ex.network.parameter_index(name))];
    };
    CHECK(unit_of("m") == "kg");
    CHECK(unit_of("k_m") == "N/m");
    CHECK(unit_of("c_m") == "N s/m");
    CHECK(unit_of("c_r") == "N s/m");
    CHECK(unit_of("F_c") == "N");
    CHECK(unit_of("v0") == "m/s");
    CHECK(unit_of("J_s") == "kg m^2");  // the shaft stays rotational
    CHECK(unit_of("k_s") == "N m/rad");
    CHECK(input_unit(ex.network, 0) == "N");
    const auto output = [&](std::size_t k) {
        return output_unit(ex.network, ex.network.outputs[static_cast<std::size_t>(ex.output_indices[k])]);
    };
    CHECK(output(0) == "m");
    CHECK(output(1) == "m/s");
    CHECK(output(2) == "N");
    CHECK(output(3) == "rad/s");
    CHECK(ex.outputs[0].scale == 1e-3);  // mm read as m
    CHECK(translational_unit("N m s^2/rad^2") == "N s^2/m^2");
    CHECK(translational_unit("1/(kg m^2)") == "1/kg");
    CHECK(translational_unit("W") == "W");
}

}  // namespace TVID_UNITY_ID

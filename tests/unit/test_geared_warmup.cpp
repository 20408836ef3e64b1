// A measured start with a warm-up shot onto the encoder, on a geared line: the shooting
// moves every node's angle and speed through the gear ratios, so a recording made by the
// model itself is reproduced from the measured encoder alone.
#include <catch2/catch.hpp>
#include <cmath>
#include <numbers>
#include <string>
#include <vector>

#include "support/test_files.hpp"
#include "tvid/estimation/identification_problem.hpp"
#include "tvid/experiment/experiment.hpp"
#include "tvid/model/steady_motion.hpp"
#include "tvid/sim/simulate.hpp"

namespace TVID_UNITY_ID {  // unique to this file in a unity build (tests/CMakeLists.txt)

using namespace tvid;

TEST_CASE("a shot warm-up turns a geared line through its ratio and reproduces the recording", "[estimation][shooting]") {
    // motor (J 0.01) =gear 1:3, k 500, c 0.5= load (J 0.05, friction 0.1), driven on the motor by
    // T = 1.1 + 0.2 sin(2π 5 t); recorded: the motor's angle [deg] and speed.
    NetworkSpec spec;
    spec.preset = "custom";
    spec.input_names = {"T"};
    spec.nodes = {NodeSpec{"motor", Field::value(0.01), false}, NodeSpec{"load", Field::value(0.05), false}};
    GearMeshSpec gear;
    gear.name = "gear";
    gear.a = 0;
    gear.b = 1;
    gear.ratio = Field::value(3.0);
    gear.k = Field::value(500.0);
    gear.c = Field::value(0.5);
    spec.gear_meshes.push_back(gear);
    spec.frictions.push_back(FrictionSpec{"loss", 1, Field::value(0.1)});
    spec.torques.push_back(TorqueSpec{"drive", 0, 0, Field::value(0.0), Field::value(1.0)});
    NetworkModel<double> model(spec);
    model.set_parameters(nullptr);
    const auto torque = [](double t) { return 1.1 + 0.2 * std::sin(2 * std::numbers::pi * 5 * t); };
    std::vector<double> time, u;
    for (int i = 0; i <= 2000; ++i) {
        time.push_back(i * 1e-3);
        u.push_back(torque(i * 1e-3));
    }
    const InputChannels inputs(time, {u});
    const double u0 = u[0];
    const SteadyMotion steady = solve_steady_motion(model, &u0, 0, 100.0, 0.0);
    REQUIRE(steady.found);
    std::vector<double> x = steady.x, angle{x[0]}, speed{x[2]};
    SimulationSettings settings;
    settings.max_step = 1e-4;
    SimulationBuffers buffers;
    const auto record = [&](std::size_t, const std::vector<double>& state, const std::vector<double>&) {
        angle.push_back(state[0]);
        speed.push_back(state[2]);
        return true;
    };
    REQUIRE(simulate_samples(model, inputs, 0, 2000, x, settings, buffers, record) == SimulationStatus::ok);

    test::TempDir dir;
    std::string csv = "t,T,angle_deg,w\n";
    char row[160];
    for (std::size_t i = 0; i < time.size(); ++i) {
        std::snprintf(row, sizeof row, "%.6f,%.17g,%.17g,%.17g\n", time[i], u[i], angle[i] * 180 / std::numbers::pi,
                      speed[i]);
        csv += row;
    }
    dir.write("rec.csv", csv);
    const auto file = dir.write("geared.yaml", R"(tvid: 1
name: geared-warmup
data: { file: rec.csv, time: t, angle: angle_deg, angle_node: motor }
model:
  nodes: [ { name: motor, J: 0.01 }, { name: load, J: 0.05 } ]
  elements:
    - { type: torque, name: drive, node: motor, input: T }
    - { type: gear_mesh, name: gear, between: [motor, load], ratio: 3, k: k_g, c: 0.5 }
    - { type: friction, name: loss, node: load, c: 0.1 }
inputs: { T: T }
outputs: { w: { column: w, speed: motor } }
parameters: { k_g: { init: 500, min: 100, max: 1000 } }
windows:
  estimation: [ { time: [1.0, 1.8] } ]
  warmup: 0.4
initial_state: measured
simulation: { method: rk4, step: 1.0e-4 }
estimation: { cost: l2, optimizer: lm }
)");
    const Experiment ex = load_experiment(file);
    const IdentificationProblem problem(ex);
    auto ws = problem.make_workspace();
    const double k = 500;
    // The encoder's motion is met and the load follows at a third of it: the recording
    // again, to the shooting's tolerance (801 samples of a ~100 rad/s speed).
    CHECK(problem.cost(&k, *ws) < 1e-12);
}

}  // namespace TVID_UNITY_ID

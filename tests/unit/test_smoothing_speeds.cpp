// A dry friction's or a road load's smoothing speed, where the experiment does not give it,
// comes from the data's own scale: 1 % of the largest speed the recordings show across the
// element (a linear axis at 0.2 m/s is smoothed over 2 mm/s, not over 0.1), carried through
// gear ratios from a measured node, or two measured nodes' relative speed; the fixed
// default only where no recorded speed reaches the element. The share of the moving samples
// within 3 smoothing speeds of zero is what the verdict warns on.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <sstream>
#include <string>

#include "support/test_files.hpp"
#include "tvid/experiment/experiment.hpp"
#include "tvid/experiment/smoothing_speeds.hpp"

namespace TVID_UNITY_ID {  // unique to this file in a unity build (tests/CMakeLists.txt)

using namespace tvid;

namespace {

// 4 s at 1 kHz: a cart's speed rising to `top` and back through zero (a sine), its
// force, a motor's speed (ratio times the cart's) and an idle column.
std::string recording(double top) {
    std::ostringstream csv;
    csv.precision(12);
    csv << "t,F,v,w,zero\n";
    for (int i = 0; i <= 4000; ++i) {
        const double t = 0.001 * i;
        const double v = top * std::sin(2 * 3.14159265358979 * 0.5 * t);
        csv << t << "," << 3 * std::cos(t) << "," << v << "," << 40 * v << ",0\n";
    }
    return csv.str();
}

Experiment loaded(const test::TempDir& dir, const std::string& elements, const std::string& outputs) {
    const std::string text = R"(tvid: 1
name: smoothing
data: { file: rec.csv, time: t }
model:
  nodes:
    - { name: motor, J: 0.001 }
    - { name: cart, J: 2, motion: linear }
  elements:
    - { type: torque, name: drive, node: cart, input: F }
    - { type: gear_mesh, name: screw, between: [motor, cart], ratio: 40, k: 1.0e6, c: 10 }
)" + elements + R"(
inputs: { F: F }
outputs:
)" + outputs + R"(
parameters:
  Fc: { init: 3, min: 0, max: 10 }
windows:
  estimation: [ { time: [0, 4] } ]
initial_state: rest
simulation: { method: rk4, step: 1.0e-3 }
estimation: { cost: l2, optimizer: lm }
)";
    return load_experiment(dir.write("e.yaml", text));
}

const SmoothingChoice& choice_of(const Experiment& ex, const std::string& element) {
    const auto it = std::find_if(ex.smoothing.begin(), ex.smoothing.end(),
                                 [&](const SmoothingChoice& c) { return c.element == element; });
    REQUIRE(it != ex.smoothing.end());
    return *it;
}

}  // namespace

TEST_CASE("a dry friction's smoothing speed is 1 % of the largest speed recorded across it", "[experiment][friction]") {
    test::TempDir dir;
    dir.write("rec.csv", recording(0.2));
    const std::string guide = "    - { type: friction, name: guide, node: cart, coulomb: Fc }";
    const std::string speed = "  v: { column: v, speed: cart }";

    SECTION("a measured linear axis at 0.2 m/s: 2 mm/s, in m/s") {
        const Experiment ex = loaded(dir, guide, speed);
        const SmoothingChoice& c = choice_of(ex, "guide");
        CHECK_FALSE(c.given);
        CHECK(c.unit == "m/s");
        CHECK(c.largest_speed == Approx(0.2).epsilon(1e-6));
        CHECK(c.speed == Approx(0.002).epsilon(1e-6));
        CHECK(ex.network.frictions[0].smoothing_speed.constant == Approx(0.002).epsilon(1e-6));
        CHECK(c.basis.find("1 % of 0.2 m/s") != std::string::npos);
        CHECK(c.basis.find("node cart") != std::string::npos);
        // A sine: 3 smoothing speeds (6 mm/s) hold under 2/pi * asin(0.03) = 1.9 % of its motion.
        CHECK(c.share_within > 0.0);
        CHECK(c.share_within < 0.02);
    }
    SECTION("given, it stays, and a wide one is seen to hold much of the motion") {
        const Experiment ex =
            loaded(dir, "    - { type: friction, name: guide, node: cart, coulomb: Fc, smoothing_speed: 0.1 }", speed);
        const SmoothingChoice& c = choice_of(ex, "guide");
        CHECK(c.given);
        CHECK(c.basis == "given");
        CHECK(ex.network.frictions[0].smoothing_speed.constant == 0.1);
        // 3 × 0.1 m/s covers the whole sine of amplitude 0.2.
        CHECK(c.share_within == 1.0);
    }
    SECTION("through the screw's ratio: the motor turns 40 times the cart's speed") {
        const Experiment ex = loaded(dir, "    - { type: friction, name: bearing, node: motor, coulomb: Fc }", speed);
        const SmoothingChoice& c = choice_of(ex, "bearing");
        CHECK(c.unit == "rad/s");
        CHECK(c.speed == Approx(0.01 * 0.2 * 40).epsilon(1e-6));
        CHECK(c.basis.find("through the gear ratios") != std::string::npos);
        CHECK(c.share_within < 0);  // no channel reads the motor's speed sample by sample
    }
    SECTION("between two measured nodes: their relative speed") {
        const Experiment ex = loaded(dir, "    - { type: friction, name: slip, between: [motor, cart], coulomb: Fc }",
                                     speed + "\n  w: { column: w, speed: motor }");
        const SmoothingChoice& c = choice_of(ex, "slip");
        CHECK(c.largest_speed == Approx(0.2 * 39).epsilon(1e-6));  // 40 v − v
        CHECK(c.speed == Approx(0.01 * 0.2 * 39).epsilon(1e-6));
        CHECK(c.basis.find("nodes motor and cart, relative") != std::string::npos);
    }
    SECTION("no recorded speed reaches it: the fixed default, said so") {
        const Experiment ex =
            loaded(dir, guide, "  T: { column: F, torque: screw }");
        const SmoothingChoice& c = choice_of(ex, "guide");
        CHECK(c.speed == 0.1);
        CHECK(ex.network.frictions[0].smoothing_speed.constant == 0.1);
        CHECK(c.basis.find("fixed default") != std::string::npos);
    }
    SECTION("a road load likewise; a viscous friction has no smoothing to choose") {
        const Experiment ex = loaded(dir,
                                     "    - { type: road_load, name: road, node: cart, a: Fc }\n"
                                     "    - { type: friction, name: viscous, node: cart, c: 5 }",
                                     speed);
        REQUIRE(ex.smoothing.size() == 1);
        CHECK(choice_of(ex, "road").speed == Approx(0.002).epsilon(1e-6));
        CHECK(ex.network.road_loads[0].smoothing_speed.constant == Approx(0.002).epsilon(1e-6));
    }
}

TEST_CASE("a stuck axis's samples are not counted as smoothed motion", "[experiment][friction]") {
    // Half the recording stuck (the speed reads noise of 1 mm/s), half moving at 0.2 m/s: the
    // smoothing of 2 mm/s holds none of the motion.
    test::TempDir dir;
    std::ostringstream csv;
    csv.precision(12);
    csv << "t,F,v\n";
    unsigned state = 12345;
    for (int i = 0; i <= 4000; ++i) {
        state = state * 1103515245u + 12345u;
        const double noise = 0.001 * ((static_cast<double>(state >> 8) / 16777216.0) * 2 - 1) * 1.7;
        const double t = 0.001 * i;
        csv << t << ",1," << (i < 2000 ? noise : 0.2 + noise) << "\n";
    }
    dir.write("rec.csv", csv.str());
    const Experiment ex = load_experiment(dir.write("e.yaml", R"(tvid: 1
name: stuck
data: { file: rec.csv, time: t }
model:
  nodes: [ { name: cart, J: m, motion: linear } ]
  elements:
    - { type: torque, name: drive, node: cart, input: F }
    - { type: friction, name: guide, node: cart, coulomb: 3 }
inputs: { F: F }
outputs: { v: { column: v, speed: cart } }
parameters: { m: { init: 2, min: 0.1, max: 10 } }
windows: { estimation: [ { time: [0, 4] } ] }
initial_state: rest
simulation: { method: rk4, step: 1.0e-3 }
estimation: { cost: l2, optimizer: lm }
)"));
    const SmoothingChoice& c = ex.smoothing.at(0);
    CHECK(c.speed == Approx(0.01 * 0.2).epsilon(0.01));
    CHECK(c.share_within == 0.0);
}

}  // namespace TVID_UNITY_ID

// The engine-block model of the methodology paper: slider-crank kinematics, the cylinder element with
// its reciprocating mass, crank-angle channels, and the engine_block preset.
#include <catch2/catch.hpp>
#include <cmath>
#include <numbers>

#include "tvid/model/network_model.hpp"
#include "tvid/model/presets.hpp"
#include "tvid/model/slider_crank.hpp"
#include "tvid/sim/simulate.hpp"

namespace TVID_UNITY_ID {  // unique to this file in a unity build (tests/CMakeLists.txt)

using namespace tvid;

namespace {

constexpr double kPi = std::numbers::pi;
const PresetConstants kEngine = {{"bore", {0.079}},   {"crank_radius", {0.0405}}, {"rod_length", {0.129}},
                                 {"K21", {8.0e4}},    {"Kxx", {3.0e5}},           {"K32", {2.0e5}},
                                 {"p_atm", {101300.0}}};
// J1 J2 J3 m C1 C2 C3 C21 C32 Cxx
const std::vector<double> kTruth = {0.0045, 0.0012, 0.12, 0.45, 0.010, 0.020, 0.025, 2.5, 4.0, 1.5};

// Kinetic energy of the inertias and pistons plus the elastic energy of the shaft.
double energy(const NetworkSpec& spec, const std::vector<double>& p, const std::vector<double>& x) {
    const std::size_t n = spec.nodes.size();
    double e = 0.0;
    for (std::size_t i = 0; i < n; ++i) e += 0.5 * p[static_cast<std::size_t>(spec.nodes[i].inertia.parameter)] * x[n + i] * x[n + i];
    for (const CylinderSpec& c : spec.cylinders) {
        const auto node = static_cast<std::size_t>(c.node);
        const double ds = slider_crank(x[node] + c.phase, 0.0405, 0.129).ds;
        e += 0.5 * p[3] * ds * ds * x[n + node] * x[n + node];  // piston: ½ m (s' ω)²
    }
    for (const SpringDamperSpec& s : spec.spring_dampers) {
        const double twist = x[static_cast<std::size_t>(s.a)] - x[static_cast<std::size_t>(s.b)];
        e += 0.5 * s.k.constant * twist * twist;
    }
    return e;
}

}  // namespace

TEST_CASE("slider-crank s' and s'' match numeric derivatives of s", "[engine]") {
    const double r = 0.0405, l = 0.129, h = 1e-5;
    for (double phi = -7.0; phi <= 7.0; phi += 0.173) {
        const auto m = slider_crank(phi, r, l);
        const double ds_num = (slider_crank(phi + h, r, l).s - slider_crank(phi - h, r, l).s) / (2 * h);
        const double dds_num = (slider_crank(phi + h, r, l).ds - slider_crank(phi - h, r, l).ds) / (2 * h);
        CHECK(m.ds == Approx(ds_num).margin(1e-10));
        CHECK(m.dds == Approx(dds_num).margin(1e-9));
    }
    // TDC and BDC: no travel at TDC, full stroke 2r at BDC, no lever arm at either.
    CHECK(slider_crank(0.0, r, l).s == Approx(0.0).margin(1e-15));
    CHECK(slider_crank(kPi, r, l).s == Approx(2 * r));
    CHECK(slider_crank(kPi, r, l).ds == Approx(0.0).margin(1e-15));
    // Without the rod's obliquity (l → ∞) s' tends to r sin φ.
    CHECK(slider_crank(0.7, r, 1e6).ds == Approx(r * std::sin(0.7)).epsilon(1e-7));
}

TEST_CASE("crank-angle channels interpolate linearly in the angle and hold the ends", "[engine]") {
    const CrankAngleChannels ch({0.0, 1.0, 3.0}, {{10.0, 20.0, 0.0}});
    std::size_t cursor = 0;
    CHECK(ch.at(0, 0.5, cursor) == 15.0);
    CHECK(ch.at(0, 2.0, cursor) == 10.0);
    CHECK(ch.at(0, 0.25, cursor) == 12.5);  // backwards works
    CHECK(ch.at(0, -4.0, cursor) == 10.0);
    CHECK(ch.at(0, 9.0, cursor) == 0.0);
}

TEST_CASE("engine_block builds the methodology paper network", "[engine]") {
    const NetworkSpec spec = build_preset("engine_block", kEngine);
    REQUIRE(spec.nodes.size() == 6);
    CHECK(spec.nodes.front().name == "damping_wheel");
    CHECK(spec.nodes.back().name == "flywheel");
    CHECK(spec.spring_dampers.size() == 5);
    CHECK(spec.frictions.size() == 6);
    REQUIRE(spec.cylinders.size() == 4);
    CHECK(spec.angle_input_names == std::vector<std::string>{"p_cyl1", "p_cyl2", "p_cyl3", "p_cyl4"});
    // Firing order 1-3-4-2: cylinder 3 fires 180°, cylinder 4 360°, cylinder 2 540° after cylinder 1.
    CHECK(spec.cylinders[0].phase == Approx(0.0));
    CHECK(spec.cylinders[2].phase == Approx(-kPi));
    CHECK(spec.cylinders[3].phase == Approx(-2 * kPi));
    CHECK(spec.cylinders[1].phase == Approx(-3 * kPi));
    CHECK(spec.output_index("omega_dw") == 0);
    // Six cylinders with their usual order, and constants that cannot work.
    PresetConstants six = kEngine;
    six["cylinders"] = {6};
    CHECK(build_preset("engine_block", six).cylinders.size() == 6);
    PresetConstants bad = kEngine;
    bad["firing_order"] = {1, 3, 3, 2};
    CHECK_THROWS_AS(build_preset("engine_block", bad), PresetConstantError);
    bad = kEngine;
    bad.erase("Kxx");
    CHECK_THROWS_AS(build_preset("engine_block", bad), PresetConstantError);
    bad = kEngine;
    bad["rod_length"] = {0.03};
    CHECK_THROWS_AS(build_preset("engine_block", bad), PresetConstantError);
}

TEST_CASE("the undamped, unforced engine chain conserves energy, pistons included", "[engine]") {
    const NetworkSpec spec = build_preset("engine_block", kEngine);
    std::vector<double> p = kTruth;
    for (std::size_t k = 4; k < p.size(); ++k) p[k] = 0.0;  // no friction, no damping
    NetworkModel<double> model(spec);
    // Atmospheric pressure in every cylinder: no gas torque.
    const std::vector<double> grid{-1e3, 1e3};
    const CrankAngleChannels pressures(grid, std::vector<std::vector<double>>(4, {101300.0, 101300.0}));
    model.set_crank_angle_inputs(&pressures);
    model.set_parameters(p.data());

    std::vector<double> time(2001);
    for (std::size_t i = 0; i < time.size(); ++i) time[i] = 2e-5 * static_cast<double>(i);  // 40 ms
    const InputChannels none(time, {});
    // Spinning at 130 rad/s with a twisted shaft: torsional oscillation on top of rotation,
    // and the pistons trade kinetic energy with the rotation as the crank turns.
    std::vector<double> x(12, 0.0);
    for (std::size_t i = 0; i < 6; ++i) {
        x[i] = 0.002 * static_cast<double>(i % 3);
        x[6 + i] = 130.0;
    }
    const double e0 = energy(spec, p, x);
    SimulationSettings s;
    s.method = IntegrationMethod::dopri5;
    s.rtol = 1e-11;
    s.atol = 1e-11;
    SimulationBuffers buffers;
    double worst = 0.0, speed_swing = 0.0;
    const auto status = simulate_samples(model, none, 0, time.size() - 1, x, s, buffers,
                                         [&](std::size_t, const std::vector<double>& xs, const std::vector<double>&) {
                                             worst = std::max(worst, std::abs(energy(spec, p, xs) - e0) / e0);
                                             speed_swing = std::max(speed_swing, std::abs(xs[6] - 130.0));
                                             return true;
                                         });
    REQUIRE(status == SimulationStatus::ok);
    CHECK(worst < 1e-8);
    CHECK(speed_swing > 0.5);  // the motion is far from trivial
}

TEST_CASE("a cylinder's gas pressure turns the crank forward after top dead centre", "[engine]") {
    const NetworkSpec spec = build_preset("engine_block", kEngine);
    NetworkModel<double> model(spec);
    // 20 bar in cylinder 1 only.
    const std::vector<double> grid{-1e3, 1e3};
    std::vector<std::vector<double>> p(4, {101300.0, 101300.0});
    p[0] = {20e5, 20e5};
    const CrankAngleChannels pressures(grid, p);
    model.set_crank_angle_inputs(&pressures);
    model.set_parameters(kTruth.data());
    std::vector<double> x(12, 0.0), dx(12);
    for (std::size_t i = 0; i < 6; ++i) x[i] = 0.3;  // 17° after cylinder 1's TDC
    model.derivative(x.data(), nullptr, dx.data());
    const double area = kPi / 4 * 0.079 * 0.079;
    const double torque = (20e5 - 101300.0) * area * slider_crank(0.3, 0.0405, 0.129).ds;
    CHECK(torque > 0);
    CHECK(model.element_torque(ElementRef{ElementKind::cylinder, 0}, x.data(), x.data() + 6, nullptr) ==
          Approx(torque));
    // At rest the only torque on throw 1 is the gas torque; the piston mass adds m·s'² to its inertia.
    const double ds = slider_crank(0.3, 0.0405, 0.129).ds;
    CHECK(dx[6 + 1] == Approx(torque / (kTruth[1] + kTruth[3] * ds * ds)));
    CHECK(dx[6 + 2] == 0.0);
}

}  // namespace TVID_UNITY_ID

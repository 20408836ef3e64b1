// A rigid gear (lib/tvid/model/elements/ideal_gear.hpp, model/rigid_gears.hpp): its nodes share
// one coordinate through the ratio; their inertias add as reflected; the loss acts on the
// transmitted torque by the direction of power flow. Against hand-derived results.
#include <catch2/catch.hpp>
#include <cmath>

#include "tvid/analysis/linear_network.hpp"
#include "tvid/analysis/torsional_modes.hpp"
#include "tvid/model/dual.hpp"
#include "tvid/model/equilibrium.hpp"
#include "tvid/model/network_model.hpp"
#include "tvid/model/rigid_gears.hpp"
#include "tvid/model/steady_motion.hpp"

namespace TVID_UNITY_ID {  // unique to this file in a unity build (tests/CMakeLists.txt)

using namespace tvid;

namespace {

NodeSpec node(const std::string& name, double j) { return NodeSpec{name, Field::value(j), false}; }

IdealGearSpec gear(int a, int b, Field ratio, Field efficiency = Field::value(1.0)) {
    IdealGearSpec g;
    g.name = "gearbox";
    g.a = a;
    g.b = b;
    g.ratio = ratio;
    g.lossy = !(efficiency.constant == 1.0 && !efficiency.is_parameter());
    g.efficiency = efficiency;
    return g;
}

// motor (J 0.2, torque input 0) =ideal gear 3.5, efficiency p[0]= out (J 0.005)
// -shaft (k, c)- load (J 1.2, torque input 1).
NetworkSpec launch_line(double k = 6000.0, double c = 15.0) {
    NetworkSpec spec;
    spec.preset = "custom";
    spec.input_names = {"T_motor", "T_load"};
    spec.parameter_names = {"eta"};
    spec.nodes = {node("motor", 0.2), node("out", 0.005), node("load", 1.2)};
    spec.ideal_gears.push_back(gear(0, 1, Field::value(3.5), Field::param(0)));
    spec.spring_dampers.push_back(SpringDamperSpec{"shaft", 1, 2, Field::value(k), Field::value(c)});
    spec.torques.push_back(TorqueSpec{"drive", 0, 0, Field::value(0.0), Field::value(1.0)});
    spec.torques.push_back(TorqueSpec{"brake", 2, 1, Field::value(0.0), Field::value(1.0)});
    return spec;
}

}  // namespace

TEST_CASE("an ideal gear's nodes accelerate together, the loss by the direction of power flow", "[model][ideal_gear]") {
    const NetworkSpec spec = launch_line();
    NetworkModel<Dual> model(spec);
    const double eta = 0.93, n = 3.5, ja = 0.2, jb = 0.005;
    const Dual p[1] = {Dual::variable(eta, 0, 1)};
    model.set_parameters(p);
    struct Case {
        double motor_torque, shaft_twist, speed;
        double factor;  // f: η when the motor drives, 1/η when the shaft drives the motor
    };
    // The shaft's torque on out is −6000·twist. A motor pushing a resisting shaft forwards drives
    // (η); a shaft that pulls forwards against a braking motor drives it (1/η); backwards the same.
    for (const Case c : {Case{40.0, 0.01, 50.0, eta}, Case{-40.0, -0.01, 50.0, 1 / eta},
                         Case{-40.0, -0.01, -50.0, eta}, Case{40.0, 0.01, -50.0, 1 / eta}}) {
        INFO("motor torque " << c.motor_torque << ", speed " << c.speed);
        const double u[2] = {c.motor_torque, 0.0};
        const Dual x[6] = {Dual(0.0), Dual(c.shaft_twist), Dual(0.0), Dual(c.speed), Dual(c.speed / n), Dual(c.speed / n)};
        Dual f[6];
        model.derivative(x, u, f);
        const double ta = c.motor_torque, tb = -6000.0 * c.shaft_twist;
        // J_b ω̇_b = T_b + n f τ, J_a ω̇_a = T_a − τ, ω̇_a = n ω̇_b.
        const double wb = (tb + n * c.factor * ta) / (jb + n * n * c.factor * ja);
        CHECK(f[4].value() == Approx(wb).epsilon(1e-12));
        CHECK(f[3].value() == Approx(n * wb).epsilon(1e-12));
        CHECK(f[5].value() == Approx(6000.0 * c.shaft_twist / 1.2).epsilon(1e-12));  // the load sees the shaft alone
        // the power flows as the case says: τ ω_a > 0 when the motor drives
        const double tau = ta - ja * n * wb;
        CHECK((tau * c.speed > 0) == (c.factor == eta));
        // d ω̇_b / dη by the quotient rule, s = ±1 (f = η^s)
        const double s = c.factor == eta ? 1.0 : -1.0, df = s * std::pow(eta, s - 1);
        const double num = tb + n * c.factor * ta, den = jb + n * n * c.factor * ja;
        CHECK(f[4].derivative(0) == Approx((n * ta * den - num * n * n * ja) / (den * den) * df).epsilon(1e-9));
    }
    // At rest no loss acts; a lossless gear is the reflected inertia exactly.
    const double u[2] = {40.0, 0.0};
    const Dual rest[6] = {Dual(0.0), Dual(0.0), Dual(0.0), Dual(0.0), Dual(0.0), Dual(0.0)};
    Dual f[6];
    model.derivative(rest, u, f);
    CHECK(f[4].value() == Approx(n * 40.0 / (jb + n * n * ja)).epsilon(1e-12));
}

TEST_CASE("a gear chain: both orientations reduce to the reflected inertia", "[model][ideal_gear]") {
    // a (J 1) =3= b (J 2) and c (J 0.5) =2= b: c is a gear's a side, b its b side; torque 6 on c.
    NetworkSpec spec;
    spec.preset = "custom";
    spec.input_names = {"T"};
    spec.nodes = {node("a", 1.0), node("b", 2.0), node("c", 0.5)};
    spec.ideal_gears.push_back(gear(0, 1, Field::value(3.0)));
    spec.ideal_gears.push_back(gear(2, 1, Field::value(2.0)));
    spec.torques.push_back(TorqueSpec{"drive", 2, 0, Field::value(0.0), Field::value(1.0)});
    const RigidGearPlan plan = plan_rigid_gears(spec);
    CHECK(plan.roots == std::vector<std::size_t>{0});
    CHECK(plan.dependent(1));
    CHECK(plan.dependent(2));
    NetworkModel<double> model(spec);
    model.set_parameters(nullptr);
    CHECK(model.tie_factor(1) == Approx(1.0 / 3.0));
    CHECK(model.tie_factor(2) == Approx(2.0 / 3.0));
    const double u[1] = {6.0};
    const double x[6] = {0, 0, 0, 3.0, 1.0, 2.0};
    double f[6];
    model.derivative(x, u, f);
    // In b's coordinate: J = 2 + 9·1 + 4·0.5 = 13, torque 2·6 = 12.
    CHECK(f[4] == Approx(12.0 / 13.0).epsilon(1e-14));
    CHECK(f[3] == Approx(3 * 12.0 / 13.0).epsilon(1e-14));
    CHECK(f[5] == Approx(2 * 12.0 / 13.0).epsilon(1e-14));
}

TEST_CASE("an ideal gear's steady motion, equilibrium and modes are the reduced line's", "[model][ideal_gear]") {
    SECTION("steady motion: the shaft carries the load through the loss, for any efficiency") {
        for (const double eta : {0.5, 0.93, 1.0}) {
            NetworkSpec spec = launch_line();
            spec.frictions.push_back(FrictionSpec{"bearing", 2, Field::value(3.0)});
            NetworkModel<double> model(spec);
            model.set_parameters(&eta);
            const double u[2] = {30.0 / (3.5 * eta), 0.0};  // 30 N m at the load's 10 rad/s
            const SteadyMotion s = solve_steady_motion(model, u, 2, 10.0, 0.0);
            INFO("eta " << eta << ": " << s.problem);
            REQUIRE(s.found);
            CHECK(s.acceleration == Approx(0.0).margin(1e-9));
            CHECK(6000.0 * (s.x[1] - s.x[2]) == Approx(30.0).epsilon(1e-9));
            CHECK(s.x[0] == Approx(3.5 * s.x[1]).epsilon(1e-12));  // the tie holds
            CHECK(s.x[3] == Approx(35.0));
            // and the simulation stays there
            std::vector<double> dxdt(6);
            model.derivative(s.x.data(), u, dxdt.data());
            for (std::size_t i = 3; i < 6; ++i) CHECK(dxdt[i] == Approx(0.0).margin(1e-9));
        }
    }
    SECTION("static equilibrium by virtual work") {
        // motor on a ground spring k1 = 100, out on k2 = 50; torque 7 on the motor.
        NetworkSpec spec = launch_line();
        spec.spring_dampers.clear();
        spec.spring_dampers.push_back(SpringDamperSpec{"k1", 0, kGround, Field::value(100.0), Field::value(0.0)});
        spec.spring_dampers.push_back(SpringDamperSpec{"k2", 1, kGround, Field::value(50.0), Field::value(0.0)});
        spec.spring_dampers.push_back(SpringDamperSpec{"k3", 2, kGround, Field::value(20.0), Field::value(0.0)});
        NetworkModel<double> model(spec);
        const double eta = 0.9;
        model.set_parameters(&eta);
        const double u[2] = {7.0, 4.0};
        const EquilibriumResult eq = solve_equilibrium(model, u);
        REQUIRE(eq.found);
        const double n = 3.5, out = n * 7.0 / (n * n * 100.0 + 50.0);  // n T δθ_b = (n² k1 + k2) θ_b δθ_b
        CHECK(eq.theta[1] == Approx(out).epsilon(1e-9));
        CHECK(eq.theta[0] == Approx(n * out).epsilon(1e-9));
        CHECK(eq.theta[2] == Approx(4.0 / 20.0).epsilon(1e-9));
    }
    SECTION("modes: one coordinate for both nodes, J = J_out + n² J_motor") {
        NetworkSpec spec = launch_line(6000.0, 0.0);
        const double eta = 1.0;  // lossless: the linearisation is exact
        spec.ideal_gears[0].lossy = false;
        spec.ideal_gears[0].efficiency = Field::value(1.0);
        const std::vector<double> x(6, 0.0), u(2, 0.0);
        const LinearNetwork sys = linearise_network(spec, {eta}, nullptr, x, u, AngleDependence::revolution_mean);
        CHECK(sys.A.rows() == 4);  // motor and out share a coordinate
        const ModalAnalysis m = torsional_modes(sys, node_ratios(spec, {eta}, 0), 0);
        const double j = 0.005 + 3.5 * 3.5 * 0.2, k = 6000.0;
        const double expected = std::sqrt(k * (1.0 / j + 1.0 / 1.2)) / (2 * 3.141592653589793);
        bool found = false;
        for (const TorsionalMode& mode : m.modes) {
            if (mode.kind != ModeKind::oscillating) continue;
            found = true;
            CHECK(mode.frequency_hz == Approx(expected).epsilon(1e-9));
            // the motor turns 3.5 times the out node in the mode's shape
            CHECK(std::abs(mode.shape[0] / mode.shape[1] - 3.5) < 1e-9);
        }
        CHECK(found);
    }
}

TEST_CASE("ideal gears around a loop, or on a prescribed or cylinder node, are refused", "[model][ideal_gear]") {
    NetworkSpec spec;
    spec.preset = "custom";
    spec.nodes = {node("a", 1.0), node("b", 1.0), node("c", 1.0)};
    spec.ideal_gears.push_back(gear(0, 1, Field::value(2.0)));
    spec.ideal_gears.push_back(gear(1, 2, Field::value(2.0)));
    std::string element;
    CHECK(rigid_gear_problem(spec, &element).empty());
    spec.ideal_gears.push_back(gear(2, 0, Field::value(0.25)));
    spec.ideal_gears.back().name = "back";
    const std::string loop = rigid_gear_problem(spec, &element);
    CHECK(loop.find("loop") != std::string::npos);
    CHECK(element == "back");
    spec.ideal_gears.pop_back();
    SpeedSourceSpec source;
    source.name = "drive";
    source.node = 2;
    spec.speed_sources.push_back(source);
    const std::string prescribed = rigid_gear_problem(spec, &element);
    CHECK(prescribed.find("speed source") != std::string::npos);
    CHECK(prescribed.find("node c") != std::string::npos);
    CHECK(element == "drive");
}

}  // namespace TVID_UNITY_ID

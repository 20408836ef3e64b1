// The position controller (lib/tvid/model/elements/position_controller.hpp): PD on the angle
// error with the derivative on the measured speed, its setpoint a channel or a constant.
#include <catch2/catch.hpp>

#include "support/text_element_source.hpp"
#include "tvid/model/dual.hpp"
#include "tvid/model/elements/position_controller.hpp"
#include "tvid/model/network_model.hpp"
#include "tvid/sim/simulate.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <vector>

namespace TVID_UNITY_ID {  // unique to this file in a unity build (tests/CMakeLists.txt)

using namespace tvid;
using tvid::test::read_error;
using tvid::test::TextSource;

TEST_CASE("a position controller pulls its node to the setpoint channel and damps its measured speed",
          "[model][position_controller]") {
    NetworkSpec net = tvid::test::two_nodes();
    TextSource given({{"node", "b"}, {"setpoint", "w"}, {"kp", "p"}, {"kd", "0.4"}});  // "w" names a channel
    read_element<elements::PositionController>(given, "servo", net);
    REQUIRE(net.position_controllers.size() == 1);
    CHECK(net.position_controllers[0].input == 0);
    OutputSpec torque;
    torque.name = "servo";
    torque.kind = OutputKind::torque;
    REQUIRE(net.find_element("servo", torque.element));
    net.outputs.push_back(torque);

    NetworkModel<Dual> model(net);
    const Dual p[1] = {Dual::variable(20.0, 0, 1)};  // kp
    model.set_parameters(p);
    const double u[1] = {1.5};                          // the setpoint [rad]
    const Dual x[4] = {Dual(0.0), Dual(1.2), Dual(0.0), Dual(-2.0)};
    Dual f[4];
    model.derivative(x, u, f);
    const double t = 20.0 * (1.5 - 1.2) - 0.4 * -2.0;  // a setpoint step gives no derivative kick: kd acts on ω
    CHECK(f[3].value() == Approx(t).epsilon(1e-15));     // J = 1
    CHECK(f[3].derivative(0) == Approx(0.3).epsilon(1e-15));
    CHECK(f[2].value() == 0.0);
    CHECK(model.output(0, x, u).value() == Approx(t).epsilon(1e-15));
    // At rest it holds the node where the setpoint is.
    double torques[2];
    NetworkModel<double> plain(net);
    const double pd[1] = {20.0}, at_setpoint[2] = {0.0, 1.5};
    plain.set_parameters(pd);
    plain.static_torques(at_setpoint, u, torques);
    CHECK(torques[1] == 0.0);
}

TEST_CASE("the position controller's reader", "[model][position_controller]") {
    NetworkSpec net = tvid::test::two_nodes();
    TextSource constant({{"node", "a"}, {"setpoint", "0.5"}, {"kp", "10"}});
    read_element<elements::PositionController>(constant, "servo", net);
    CHECK(net.position_controllers[0].input == -1);
    CHECK(net.position_controllers[0].setpoint.constant == 0.5);
    CHECK(net.position_controllers[0].kd.constant == 0.0);

    const auto read = [](TextSource& s, NetworkSpec& n) { read_element<elements::PositionController>(s, "servo", n); };
    CHECK(read_error(TextSource({{"node", "a"}, {"kp", "10"}}), read) == "setpoint: missing");
    CHECK(read_error(TextSource({{"node", "a"}, {"setpoint", "0"}, {"kp", "-1"}}), read) ==
          "kp: cannot be negative: a controller gain (got -1)");
    CHECK(read_error(TextSource({{"node", "a"}, {"setpoint", "0"}, {"kp", "10"}, {"ki", "-2"}}), read) ==
          "ki: cannot be negative: a controller gain (got -2)");
    CHECK(read_error(TextSource({{"node", "a"}, {"setpoint", "0"}, {"kp", "10"}, {"ki", "0"}}), read).empty());
    // A continuous integral lives in a hidden node of its own; ki: 0 adds none.
    NetworkSpec with_integral = tvid::test::two_nodes();
    TextSource pi({{"node", "a"}, {"setpoint", "0"}, {"kp", "10"}, {"ki", "2"}});
    read_element<elements::PositionController>(pi, "servo", with_integral);
    REQUIRE(with_integral.nodes.size() == 3);
    CHECK(with_integral.nodes[2].name == "servo.integral");
    CHECK(with_integral.position_controllers[0].integral_node == 2);
    CHECK(state_nodes(with_integral) == std::vector<std::string>{"servo.integral"});
    CHECK(net.nodes.size() == 2);
}

TEST_CASE("a position controller's command saturates at its limits", "[model][position_controller]") {
    NetworkSpec net = tvid::test::two_nodes();
    TextSource given({{"node", "b"}, {"setpoint", "2"}, {"kp", "10"}, {"kd", "1"}, {"limits", "-3,p"}});
    read_element<elements::PositionController>(given, "servo", net);
    REQUIRE(net.position_controllers[0].limited);
    NetworkModel<Dual> model(net);
    const Dual p[1] = {Dual::variable(4.0, 0, 1)};  // the upper limit
    model.set_parameters(p);
    const double u[1] = {0.0};
    const auto acceleration = [&](double theta, double omega) {
        const Dual x[4] = {Dual(0.0), Dual(theta), Dual(0.0), Dual(omega)};
        Dual f[4];
        model.derivative(x, u, f);
        return f[3];
    };
    CHECK(acceleration(1.9, 0.5).value() == Approx(10 * 0.1 - 0.5));  // inside: the PD law
    CHECK(acceleration(1.9, 0.5).derivative(0) == 0.0);
    CHECK(acceleration(0.0, 0.0).value() == 4.0);  // 20 N m asked, 4 given
    CHECK(acceleration(0.0, 0.0).derivative(0) == 1.0);
    CHECK(acceleration(5.0, 0.0).value() == -3.0);

    const auto read = [](TextSource& s, NetworkSpec& n) { read_element<elements::PositionController>(s, "servo", n); };
    CHECK(read_error(TextSource({{"node", "a"}, {"setpoint", "0"}, {"kp", "10"}, {"limits", "1,3"}}), read) ==
          "limits: expected [min, max] with min <= 0 <= max and min < max, got [1, 3]");
}

TEST_CASE("a continuous PI position controller removes the error a constant load leaves", "[model][position_controller]") {
    // Node b (J = 1) under kp = 4, ki = 2, kd = 3 towards θ_set = 1, against a constant load of −0.5 N m.
    NetworkSpec net = tvid::test::two_nodes();
    TextSource given({{"node", "b"}, {"setpoint", "1"}, {"kp", "4"}, {"ki", "2"}, {"kd", "3"}});
    read_element<elements::PositionController>(given, "servo", net);
    TorqueSpec load;
    load.name = "load";
    load.node = 1;
    load.input = -1;
    load.value = Field::value(-0.5);
    net.torques.push_back(load);
    NetworkModel<double> model(net);
    const double unused[1] = {0.0};  // two_nodes declares one parameter, p
    model.set_parameters(unused);
    std::vector<double> t(20001);
    for (std::size_t i = 0; i < t.size(); ++i) t[i] = 0.001 * static_cast<double>(i);
    const InputChannels in(t, {std::vector<double>(t.size(), 0.0)});
    std::vector<double> x(6, 0.0);  // θa, θb, θ_integral, ωa, ωb, ω_integral
    SimulationBuffers buffers;
    // The same RK4 written out on (θ, ω, I): θ' = ω, ω' = 4(1 − θ) + 2 I − 3 ω − 0.5, I' = 1 − θ.
    std::array<double, 3> y{0.0, 0.0, 0.0};
    const auto f = [](const std::array<double, 3>& s) {
        return std::array<double, 3>{s[1], 4 * (1 - s[0]) + 2 * s[2] - 3 * s[1] - 0.5, 1 - s[0]};
    };
    double worst = 0.0;
    const auto compare = [&](std::size_t, const std::vector<double>& s, const std::vector<double>&) {
        const double h = 0.001;
        const auto k1 = f(y);
        std::array<double, 3> m;
        for (int j = 0; j < 3; ++j) m[j] = y[j] + 0.5 * h * k1[j];
        const auto k2 = f(m);
        for (int j = 0; j < 3; ++j) m[j] = y[j] + 0.5 * h * k2[j];
        const auto k3 = f(m);
        for (int j = 0; j < 3; ++j) m[j] = y[j] + h * k3[j];
        const auto k4 = f(m);
        for (int j = 0; j < 3; ++j) y[j] += h / 6 * (k1[j] + 2 * k2[j] + 2 * k3[j] + k4[j]);
        worst = std::max({worst, std::abs(s[1] - y[0]), std::abs(s[4] - y[1]), std::abs(s[5] - y[2])});
        return true;
    };
    REQUIRE(simulate_samples(model, in, 0, t.size() - 1, x, SimulationSettings{}, buffers, compare) ==
            SimulationStatus::ok);
    CHECK(worst < 1e-12);
    CHECK(x[1] == Approx(1.0).margin(1e-6));    // no error left: P alone would stop at 1 − 0.5/4
    CHECK(x[5] == Approx(0.25).margin(1e-6));   // the integral carries the load: ki·I = 0.5
}

}  // namespace TVID_UNITY_ID

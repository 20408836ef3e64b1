// Sampled (digital) controllers (lib/tvid/model/elements/position_controller.hpp): the held
// command against a firmware loop written out here, on every integrator; the sensitivities
// of the held command against central differences; a sampled speed loop.
#include <catch2/catch.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <deque>
#include <vector>

#include "support/text_element_source.hpp"
#include "tvid/model/elements/speed_controller.hpp"
#include "tvid/model/packed_dual.hpp"
#include "tvid/sim/fixed_state_rk4.hpp"
#include "tvid/sim/sensitivity_system.hpp"
#include "tvid/sim/simulate.hpp"

namespace TVID_UNITY_ID {  // unique to this file in a unity build (tests/CMakeLists.txt)

using namespace tvid;
using tvid::test::read_error;
using tvid::test::TextSource;

namespace {

constexpr double kJ = 0.5, kKp = 3.0, kKi = 2.0, kKd = 0.8, kLower = -1.0, kUpper = 1.2;
constexpr double kPeriod = 0.002, kDt = 0.001;  // the controller at half the recording's rate
constexpr int kDelay = 2, kAverage = 3;
constexpr std::size_t kSamples = 1500;

// One free inertia under a sampled PID position controller; parameters J, kp, ki, kd.
NetworkSpec drive() {
    NetworkSpec spec;
    spec.parameter_names = {"J", "kp", "ki", "kd"};
    spec.input_names = {"theta_ref"};
    spec.nodes.push_back(NodeSpec{"motor", Field::param(0), false});
    PositionControllerSpec c;
    c.name = "drive";
    c.input = 0;
    c.kp = Field::param(1);
    c.ki = Field::param(2);
    c.kd = Field::param(3);
    c.limited = true;
    c.lower = Field::value(kLower);
    c.upper = Field::value(kUpper);
    c.sample_period = kPeriod;
    c.delay_periods = kDelay;
    c.angle_average = kAverage;
    spec.position_controllers.push_back(c);
    spec.outputs.push_back(OutputSpec{"theta", OutputKind::angle, 0, {}, Field::value(0.0)});
    OutputSpec torque;
    torque.name = "T";
    torque.kind = OutputKind::torque;
    REQUIRE(spec.find_element("drive", torque.element));
    spec.outputs.push_back(torque);
    return spec;
}

// Steps and a ramp of the setpoint, sampled at 1 kHz: large enough to saturate.
InputChannels setpoint_channel() {
    std::vector<double> t(kSamples + 1), ref(kSamples + 1);
    for (std::size_t i = 0; i <= kSamples; ++i) {
        t[i] = kDt * static_cast<double>(i);
        ref[i] = t[i] < 0.1 ? 0.0 : t[i] < 0.6 ? 1.5 : t[i] < 1.0 ? 1.5 - 4.0 * (t[i] - 0.6) : -0.1;
    }
    return InputChannels(t, {ref});
}

struct Trace {
    std::vector<double> theta, torque;
};

// The firmware written out: at each sample on the clock the angle is sampled, the speed is
// the difference of the last kAverage+1 angles over kAverage periods, the integral adds
// ki·Ts·error within the limits, the saturated command goes into a delay line of kDelay.
// Between samples the torque is constant, so J θ'' = T integrates exactly.
Trace firmware_reference(double theta0, double omega0, const InputChannels& in) {
    std::deque<double> angles, commands;
    for (int j = kAverage; j >= 0; --j) angles.push_back(theta0 - j * kPeriod * omega0);
    const auto clamp = [](double v) { return std::min(std::max(v, kLower), kUpper); };
    // It has held the line steady: nothing else acts on the node, so its integral makes the
    // first command zero.
    const double law0 = kKp * (in.value(0, 0) - theta0) - kKd * omega0;
    double integral = clamp(-law0);
    const double first = clamp(law0 + integral);
    commands.assign(kDelay + 1, first);
    double held = first, theta = theta0, omega = omega0;
    Trace out;
    for (std::size_t i = 1; i <= kSamples; ++i) {
        theta += omega * kDt + held * kDt * kDt / (2 * kJ);
        omega += held * kDt / kJ;
        if (i % 2 == 0) {  // on the 2 ms clock
            angles.pop_front();
            angles.push_back(theta);
            const double rate = (angles.back() - angles.front()) / (kAverage * kPeriod);
            const double error = in.value(0, i) - theta;
            integral = clamp(integral + kKi * kPeriod * error);
            commands.pop_front();
            commands.push_back(clamp(kKp * error + integral - kKd * rate));
            held = commands.front();
        }
        out.theta.push_back(theta);
        out.torque.push_back(held);
    }
    return out;
}

Trace simulate_drive(const SimulationSettings& settings, double theta0, double omega0, const InputChannels& in) {
    const NetworkSpec spec = drive();
    NetworkModel<double> model(spec);
    const double p[4] = {kJ, kKp, kKi, kKd};
    model.set_parameters(p);
    SimulationBuffers buffers;
    std::vector<double> x{theta0, omega0};
    Trace out;
    const auto record = [&](std::size_t, const std::vector<double>& state, const std::vector<double>& u) {
        out.theta.push_back(model.output(0, state.data(), u.data()));
        out.torque.push_back(model.output(1, state.data(), u.data()));
        return true;
    };
    REQUIRE(simulate_samples(model, in, 0, kSamples, x, settings, buffers, record) == SimulationStatus::ok);
    return out;
}

double largest_difference(const std::vector<double>& a, const std::vector<double>& b) {
    REQUIRE(a.size() == b.size());
    double d = 0.0;
    for (std::size_t i = 0; i < a.size(); ++i) d = std::max(d, std::abs(a[i] - b[i]));
    return d;
}

}  // namespace

TEST_CASE("a sampled controller holds the command its firmware computes, on every integrator",
          "[model][sampled_controller]") {
    const InputChannels in = setpoint_channel();
    const Trace truth = firmware_reference(0.2, 0.7, in);  // a moving start: its history turns at 0.7 rad/s
    REQUIRE(truth.torque[0] == 0.0);
    const auto saturated = std::count_if(truth.torque.begin(), truth.torque.end(),
                                         [](double t) { return t == kLower || t == kUpper; });
    REQUIRE(saturated > 20);  // the limits and the anti-windup are exercised

    SimulationSettings rk4;  // exact for a held torque: θ is quadratic in t between samples
    const Trace fixed = simulate_drive(rk4, 0.2, 0.7, in);
    CHECK(largest_difference(fixed.theta, truth.theta) < 1e-12);
    CHECK(largest_difference(fixed.torque, truth.torque) < 1e-11);

    SimulationSettings dopri5;
    dopri5.method = IntegrationMethod::dopri5;
    dopri5.rtol = 1e-10;
    dopri5.atol = 1e-12;
    const Trace adaptive = simulate_drive(dopri5, 0.2, 0.7, in);
    CHECK(largest_difference(adaptive.theta, truth.theta) < 1e-9);
    CHECK(largest_difference(adaptive.torque, truth.torque) < 1e-8);

    SimulationSettings stiff = dopri5;
    stiff.method = IntegrationMethod::rosenbrock4;
    const Trace rosenbrock = simulate_drive(stiff, 0.2, 0.7, in);
    CHECK(largest_difference(rosenbrock.theta, truth.theta) < 1e-9);
    CHECK(largest_difference(rosenbrock.torque, truth.torque) < 1e-8);

    // A second simulation on the same model restarts its memory: the same bits again.
    CHECK(simulate_drive(rk4, 0.2, 0.7, in).theta == fixed.theta);
}

TEST_CASE("a sampled controller's held command carries exact sensitivities", "[model][sampled_controller]") {
    const InputChannels in = setpoint_channel();
    const NetworkSpec spec = drive();
    const double p0[4] = {kJ, kKp, kKi, kKd};
    std::vector<double> u, u_stage;
    std::size_t rhs = 0;

    // Fixed-step RK4 over dual numbers: d(θ, T)/dp at every sample.
    NetworkModel<PackedDual<4>> dual(spec);
    std::array<PackedDual<4>, 4> p;
    for (int j = 0; j < 4; ++j) p[static_cast<std::size_t>(j)] = PackedDual<4>::variable(p0[j], j);
    dual.set_parameters(p.data());
    std::array<PackedDual<4>, 2> x{PackedDual<4>(0.2), PackedDual<4>(0.7)};
    std::vector<std::array<double, 4>> dtheta, dtorque;
    const auto record = [&](std::size_t, const std::array<PackedDual<4>, 2>& s, const std::vector<double>& ui) {
        const PackedDual<4> th = dual.output(0, s.data(), ui.data()), tq = dual.output(1, s.data(), ui.data());
        dtheta.push_back({th.derivative(0), th.derivative(1), th.derivative(2), th.derivative(3)});
        dtorque.push_back({tq.derivative(0), tq.derivative(1), tq.derivative(2), tq.derivative(3)});
        return true;
    };
    REQUIRE(march_fixed_rk4<2>(dual, in, 0, kSamples, x, 0.0, u, u_stage, rhs, record) == SimulationStatus::ok);

    // Central differences of the double simulation.
    const auto simulate = [&](const double* q) {
        NetworkModel<double> model(spec);
        model.set_parameters(q);
        SimulationBuffers buffers;
        std::vector<double> s{0.2, 0.7};
        Trace out;
        REQUIRE(simulate_samples(model, in, 0, kSamples, s, SimulationSettings{}, buffers,
                                 [&](std::size_t, const std::vector<double>& xs, const std::vector<double>& ui) {
                                     out.theta.push_back(model.output(0, xs.data(), ui.data()));
                                     out.torque.push_back(model.output(1, xs.data(), ui.data()));
                                     return true;
                                 }) == SimulationStatus::ok);
        return out;
    };
    double worst = 0.0, scale = 0.0;
    for (int j = 0; j < 4; ++j) {
        double up[4], down[4];
        std::copy_n(p0, 4, up);
        std::copy_n(p0, 4, down);
        const double h = 1e-6 * p0[j];
        up[j] += h;
        down[j] -= h;
        const Trace a = simulate(up), b = simulate(down);
        for (std::size_t i = 0; i < kSamples; ++i) {
            // Away from a saturation's edge (where the derivative jumps) the two agree.
            if (std::abs(a.torque[i] - b.torque[i]) > 0 && (a.torque[i] == kUpper || b.torque[i] == kUpper ||
                                                              a.torque[i] == kLower || b.torque[i] == kLower))
                continue;
            const double fd_theta = (a.theta[i] - b.theta[i]) / (2 * h), fd_torque = (a.torque[i] - b.torque[i]) / (2 * h);
            worst = std::max({worst, std::abs(fd_theta - dtheta[i][static_cast<std::size_t>(j)]),
                              std::abs(fd_torque - dtorque[i][static_cast<std::size_t>(j)])});
            scale = std::max({scale, std::abs(fd_theta), std::abs(fd_torque)});
        }
    }
    REQUIRE(scale > 0.1);  // the parameters move the trace
    CHECK(worst < 1e-6 * scale);

    // The augmented system of the adaptive methods (SensitivitySystem) agrees.
    NetworkModel<Dual> augmented(spec);
    std::array<Dual, 4> pd;
    for (int j = 0; j < 4; ++j) pd[static_cast<std::size_t>(j)] = Dual::variable(p0[j], j, 4);
    augmented.set_parameters(pd.data());
    std::vector<Dual> xs(2), dxdt(2);
    std::vector<double> u_now(1);
    SensitivitySystem system(augmented, in, u_now, xs, dxdt, 4);
    std::vector<double> z(2 + 2 * 4, 0.0);
    z[0] = 0.2;
    z[1] = 0.7;
    SimulationSettings dopri5;
    dopri5.method = IntegrationMethod::dopri5;
    dopri5.rtol = 1e-10;
    dopri5.atol = 1e-12;
    SimulationBuffers buffers;
    double worst_augmented = 0.0;
    const auto compare = [&](std::size_t i, const std::vector<double>& zi, const std::vector<double>&) {
        for (std::size_t j = 0; j < 4; ++j)
            worst_augmented = std::max(worst_augmented, std::abs(zi[2 + j] - dtheta[i - 1][j]));
        return true;
    };
    REQUIRE(march_samples(system, in, 0, kSamples, z, 2, dopri5, buffers, compare) == SimulationStatus::ok);
    CHECK(worst_augmented < 1e-6 * scale);
}

TEST_CASE("a sampled speed controller measures its speed by backward differences", "[model][sampled_controller]") {
    NetworkSpec net = tvid::test::two_nodes();
    TextSource given({{"node", "b"}, {"setpoint", "10"}, {"kp", "5"}, {"ki", "p"}, {"sample_period", "0.001"},
                      {"limits", "-20,20"}});
    elements::SpeedController::build(given, "loop", net);
    REQUIRE(net.position_controllers.size() == 1);
    REQUIRE(net.spring_dampers.empty());  // no reference node: the loop is one sampled element
    CHECK(net.nodes.size() == 2);
    const PositionControllerSpec& c = net.position_controllers[0];
    CHECK(c.measures == ControlledQuantity::speed);
    CHECK(c.sample_period == 0.001);

    // From rest the loop (J = 1, s² + 5 s + 20) drives node b to 10 rad/s, saturated at first.
    NetworkModel<double> model(net);
    const double p[1] = {20.0};
    model.set_parameters(p);
    std::vector<double> t(6001);
    for (std::size_t i = 0; i < t.size(); ++i) t[i] = 0.001 * static_cast<double>(i);
    const InputChannels in(t, {std::vector<double>(t.size(), 0.0)});
    std::vector<double> x{0.0, 0.0, 0.0, 0.0};
    SimulationBuffers buffers;
    double fastest = 0.0;
    const auto watch = [&](std::size_t, const std::vector<double>& s, const std::vector<double>&) {
        fastest = std::max(fastest, s[3]);
        return true;
    };
    REQUIRE(simulate_samples(model, in, 0, t.size() - 1, x, SimulationSettings{}, buffers, watch) ==
            SimulationStatus::ok);
    CHECK(x[3] == Approx(10.0).margin(1e-3));  // the integral removes the speed error
    CHECK(fastest < 12.5);                     // the clamped integral does not wind up through the saturation
    CHECK(x[2] == 0.0);                        // node a is left alone
}

TEST_CASE("a sampled controller's reader", "[model][sampled_controller]") {
    const auto position = [](TextSource& s, NetworkSpec& n) { read_element<elements::PositionController>(s, "servo", n); };
    NetworkSpec net = tvid::test::two_nodes();
    TextSource given({{"node", "a"}, {"setpoint", "0"}, {"kp", "10"}, {"ki", "3"}, {"sample_period", "0.001"},
                      {"delay", "0.002"}, {"angle_average", "4"}});
    position(given, net);
    const PositionControllerSpec& c = net.position_controllers[0];
    CHECK(c.sampled());
    CHECK(c.delay_periods == 2);
    CHECK(c.angle_average == 4);
    CHECK(c.ki.constant == 3.0);

    CHECK(read_error(TextSource({{"node", "a"}, {"setpoint", "0"}, {"kp", "10"}, {"delay", "0.001"}}), position) ==
          "delay: belongs to a sampled controller: give its sample_period too");
    CHECK(read_error(TextSource({{"node", "a"}, {"setpoint", "0"}, {"kp", "10"}, {"sample_period", "0.001"},
                                 {"delay", "0.0015"}}),
                     position)
              .rfind("delay: expected a whole number of sample periods", 0) == 0);
    CHECK(read_error(TextSource({{"node", "a"}, {"setpoint", "0"}, {"kp", "10"}, {"sample_period", "0"}}), position)
              .rfind("sample_period: expected a positive number of seconds", 0) == 0);
    CHECK(read_error(TextSource({{"node", "a"}, {"setpoint", "0"}, {"kp", "10"}, {"sample_period", "p"}}), position)
              .rfind("sample_period: expected a number of seconds", 0) == 0);
    CHECK(read_error(TextSource({{"node", "a"}, {"setpoint", "0"}, {"kp", "10"}, {"sample_period", "0.001"},
                                 {"angle_average", "2.5"}}),
                     position)
              .rfind("angle_average: expected a whole number", 0) == 0);
    // A sampled controller keeps its integral with its samples: no hidden node.
    CHECK(net.nodes.size() == 2);
    CHECK(c.integral_node == -1);
    const auto speed = [](TextSource& s, NetworkSpec& n) { elements::SpeedController::build(s, "loop", n); };
    CHECK(read_error(TextSource({{"node", "a"}, {"setpoint", "0"}, {"kp", "1"}, {"ki", "1"}, {"limits", "-1,1"}}), speed)
              .rfind("limits: belongs to a sampled speed controller", 0) == 0);
}

}  // namespace TVID_UNITY_ID

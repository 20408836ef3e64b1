// Prescribed motion (elements/speed_source.hpp) and the PI speed controller built on it,
// against hand-derived motions: a line dragged at a constant acceleration, a twisted
// shaft ringing down behind a constant-speed drive, and a PI loop's steady state.
#include <catch2/catch.hpp>
#include <cmath>
#include <vector>

#include "support/test_files.hpp"
#include "tvid/estimation/problem_definition.hpp"
#include "tvid/experiment/experiment.hpp"
#include "tvid/model/steady_motion.hpp"
#include "tvid/sim/simulate.hpp"

namespace TVID_UNITY_ID {  // unique to this file in a unity build (tests/CMakeLists.txt)

using namespace tvid;

namespace {

// n0 (J0, its speed the channel u = input 0, its slope input 1) –spring k, damper c– n1 (J1).
struct DraggedLine {
    double J0 = 0.5, J1 = 2.0, k = 400.0, c = 8.0;
    NetworkSpec spec;
    DraggedLine() {
        spec.preset = "custom";
        spec.input_names = {"w"};
        spec.input_rates = {0};
        spec.nodes = {NodeSpec{"drive", Field::value(J0), false}, NodeSpec{"driven", Field::value(J1), false}};
        spec.spring_dampers.push_back(SpringDamperSpec{"shaft", 0, 1, Field::value(k), Field::value(c)});
        spec.speed_sources.push_back(SpeedSourceSpec{"source", 0, 0, 1, Field::value(0.0), Field::value(1.0)});
        for (const char* name : {"source", "shaft"}) {
            OutputSpec o;
            o.name = name;
            o.kind = OutputKind::torque;
            REQUIRE(spec.find_element(name, o.element));
            spec.outputs.push_back(o);
        }
        OutputSpec speed;
        speed.name = "w_drive";
        speed.kind = OutputKind::speed;
        speed.node = 0;
        spec.outputs.push_back(speed);
    }
};

// Samples every `dt` over [0, end] of the speed f(t) and of its slope df(t).
template <class F, class DF>
InputChannels speed_channel(double end, double dt, F&& f, DF&& df) {
    std::vector<double> time, w, slope;
    for (int i = 0; i * dt <= end + 1e-12; ++i) {
        time.push_back(i * dt);
        w.push_back(f(i * dt));
        slope.push_back(df(i * dt));
    }
    return InputChannels(time, {w, slope});
}

}  // namespace

TEST_CASE("a speed source dragging a line at constant acceleration a applies (J0 + J1) a", "[model][speed_source]") {
    const DraggedLine line;
    NetworkModel<double> model(line.spec);
    model.set_parameters(nullptr);
    const double w0 = 50.0, a = 10.0;
    const InputChannels inputs = speed_channel(2.0, 1e-3, [&](double t) { return w0 + a * t; }, [&](double) { return a; });

    // The steady motion: the driven node lags by the twist that accelerates it, J1·a/k.
    const double u0[2] = {w0, a};
    const SteadyMotion steady = solve_steady_motion(model, u0, 0, w0, 0.0);
    REQUIRE(steady.found);
    CHECK(steady.acceleration == Approx(a).epsilon(1e-12));
    CHECK(steady.x[0] == 0.0);
    CHECK(steady.x[1] == Approx(-line.J1 * a / line.k).epsilon(1e-9));
    CHECK(steady.x[2] == w0);
    CHECK(steady.x[3] == w0);

    // Simulated from there it stays on that motion: θ0 = w0 t + a t²/2 exactly (RK4 on a
    // linear speed), the twist constant, the source's torque (J0 + J1) a, the shaft's J1 a.
    std::vector<double> x = steady.x;
    SimulationSettings settings;
    SimulationBuffers buffers;
    std::size_t checked = 0;
    const auto observe = [&](std::size_t i, const std::vector<double>& state, const std::vector<double>& u) {
        const double t = inputs.time()[i];
        CHECK(state[0] == Approx(w0 * t + 0.5 * a * t * t).epsilon(1e-12));
        CHECK(state[0] - state[1] == Approx(line.J1 * a / line.k).epsilon(1e-8));
        CHECK(state[3] == Approx(w0 + a * t).epsilon(1e-10));
        CHECK(model.output(0, state.data(), u.data()) == Approx((line.J0 + line.J1) * a).epsilon(1e-8));
        CHECK(model.output(1, state.data(), u.data()) == Approx(line.J1 * a).epsilon(1e-8));
        CHECK(model.output(2, state.data(), u.data()) == u[0]);
        ++checked;
        return true;
    };
    REQUIRE(simulate_samples(model, inputs, 0, inputs.samples() - 1, x, settings, buffers, observe) ==
            SimulationStatus::ok);
    CHECK(checked == inputs.samples() - 1);
}

TEST_CASE("a shaft twisted behind a constant-speed drive rings down as the damped oscillator", "[model][speed_source]") {
    // The drive holds Ω: the twist φ = θ0 − θ1 obeys J1 φ'' + c φ' + k φ = 0, so
    // φ(t) = φ0 e^(−ζωt) (cos ωd t + ζω/ωd sin ωd t) from φ(0) = φ0, φ'(0) = 0, and the
    // source applies the shaft's torque k φ + c φ'.
    const DraggedLine line;
    NetworkModel<double> model(line.spec);
    model.set_parameters(nullptr);
    const double omega = 30.0, phi0 = 0.02;
    const InputChannels inputs = speed_channel(1.5, 1e-3, [&](double) { return omega; }, [](double) { return 0.0; });
    const double wn = std::sqrt(line.k / line.J1), zeta = line.c / (2 * std::sqrt(line.k * line.J1));
    const double wd = wn * std::sqrt(1 - zeta * zeta);
    const auto phi = [&](double t) {
        return phi0 * std::exp(-zeta * wn * t) * (std::cos(wd * t) + zeta * wn / wd * std::sin(wd * t));
    };
    const auto phi_rate = [&](double t) { return -phi0 * wn * wn / wd * std::exp(-zeta * wn * t) * std::sin(wd * t); };
    std::vector<double> x = {0.0, -phi0, omega, omega};
    SimulationSettings settings;
    settings.max_step = 1e-4;
    SimulationBuffers buffers;
    double worst = 0.0;
    const auto observe = [&](std::size_t i, const std::vector<double>& state, const std::vector<double>& u) {
        const double t = inputs.time()[i];
        CHECK(state[0] == Approx(omega * t).epsilon(1e-13));
        CHECK(state[0] - state[1] == Approx(phi(t)).margin(1e-9));
        const double torque = line.k * phi(t) + line.c * phi_rate(t);
        CHECK(model.output(0, state.data(), u.data()) == Approx(torque).margin(1e-6));
        worst = std::max(worst, std::abs(state[0] - state[1] - phi(t)));
        return true;
    };
    REQUIRE(simulate_samples(model, inputs, 0, inputs.samples() - 1, x, settings, buffers, observe) ==
            SimulationStatus::ok);
    CHECK(worst < 1e-9);
    CHECK(std::abs(phi(1.5)) < 0.2 * phi0);  // it did ring down over the window
}

TEST_CASE("a PI speed controller holds its setpoint against a friction load", "[model][speed_source]") {
    // J ω' = T_pi − c_f ω with T_pi = kp (Ω − ω) + ki ∫(Ω − ω): the integral action leaves
    // no error, ω → Ω, and the controller then supplies c_f Ω from an integral of c_f Ω / ki.
    test::TempDir dir;
    std::string csv = "t,w_set,w\n";
    for (int i = 0; i <= 10000; ++i) csv += std::to_string(i * 1e-3) + ",100,100\n";
    dir.write("rec.csv", csv);
    const auto file = dir.write("pi.yaml", R"(tvid: 1
name: pi
data: { file: rec.csv, time: t }
model:
  nodes: [ { name: drive, J: 0.1 } ]
  elements:
    - { type: speed_controller, name: pi, node: drive, setpoint: w_set, kp: 0.5, ki: 5 }
    - { type: friction, name: loss, node: drive, c: 0.02 }
inputs: { w_set: w_set }
outputs:
  w: { column: w, speed: drive }
  T: { column: w, torque: pi }
parameters: {}
windows: { estimation: [ { time: [0, 10] } ] }
initial_state: rest
)");
    const Experiment ex = load_experiment(file);
    REQUIRE(ex.network.nodes.size() == 2);
    CHECK(ex.network.nodes[1].name == "pi.reference");
    REQUIRE(ex.network.speed_sources.size() == 1);
    CHECK(ex.network.speed_sources[0].name == "pi.setpoint");
    const ProblemDefinition d = problem_definition(ex);
    NetworkModel<double> model(d.network);
    model.set_parameters(nullptr);
    std::vector<double> x(4, 0.0);
    SimulationSettings settings;
    SimulationBuffers buffers;
    double w_end = 0.0, torque_end = 0.0, twist_end = 0.0;
    const auto observe = [&](std::size_t, const std::vector<double>& state, const std::vector<double>& u) {
        w_end = model.output(static_cast<std::size_t>(ex.output_indices[0]), state.data(), u.data());
        torque_end = model.output(static_cast<std::size_t>(ex.output_indices[1]), state.data(), u.data());
        twist_end = state[1] - state[0];
        return true;
    };
    REQUIRE(simulate_samples(model, d.inputs, 0, d.inputs.samples() - 1, x, settings, buffers, observe) ==
            SimulationStatus::ok);
    CHECK(w_end == Approx(100.0).epsilon(1e-9));
    CHECK(torque_end == Approx(0.02 * 100.0).epsilon(1e-8));
    CHECK(twist_end == Approx(0.02 * 100.0 / 5.0).epsilon(1e-8));  // the integrator's state
}

}  // namespace TVID_UNITY_ID

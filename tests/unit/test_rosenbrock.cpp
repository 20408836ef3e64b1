// The stiff integrator rosenbrock4: its Jacobian ∂f/∂x (dual numbers through the element
// code) against central differences, in one chunk and in several; its ∂f/∂t from the
// interpolated inputs; its accuracy on a two-mass network with a known solution; its
// failure statuses; and `simulation.method: rosenbrock4` in the experiment file.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "support/test_files.hpp"
#include "tvid/experiment/experiment.hpp"
#include "tvid/model/presets.hpp"
#include "tvid/model/state_jacobian.hpp"
#include "tvid/sim/simulate.hpp"
#include "tvid/sim/stiff_network_system.hpp"
#include "tvid/util/input_error.hpp"

namespace TVID_UNITY_ID {  // unique to this file in a unity build (tests/CMakeLists.txt)

using namespace tvid;

namespace {

// ∂f/∂x by central differences of the double model, row-major.
std::vector<double> difference_jacobian(NetworkModel<double>& model, const std::vector<double>& x, const double* u) {
    const std::size_t n = x.size();
    std::vector<double> J(n * n), xp = x, fp(n), fm(n);
    for (std::size_t j = 0; j < n; ++j) {
        const double h = 1e-6 * (1.0 + std::abs(x[j]));
        xp[j] = x[j] + h;
        model.derivative(xp.data(), u, fp.data());
        xp[j] = x[j] - h;
        model.derivative(xp.data(), u, fm.data());
        xp[j] = x[j];
        for (std::size_t i = 0; i < n; ++i) J[i * n + j] = (fp[i] - fm[i]) / (2 * h);
    }
    return J;
}

// The dual-number Jacobian of `model` at (x, u) against central differences, entry by
// entry, relative to the largest entry of the row.
void check_jacobian(NetworkModel<double>& model, const std::vector<double>& x, const double* u) {
    const std::size_t n = x.size();
    StateJacobian jacobian;
    jacobian.bind(model);
    REQUIRE(jacobian.state_size() == n);
    std::vector<double> J(n * n), f(n), f_double(n);
    jacobian.evaluate(x.data(), u, J.data(), f.data());
    model.derivative(x.data(), u, f_double.data());
    const std::vector<double> numeric = difference_jacobian(model, x, u);
    for (std::size_t i = 0; i < n; ++i) {
        CHECK(f[i] == f_double[i]);  // the dual model's values are the double model's, bit for bit
        double row = 0.0;
        for (std::size_t j = 0; j < n; ++j) row = std::max(row, std::abs(numeric[i * n + j]));
        for (std::size_t j = 0; j < n; ++j) {
            INFO("row " << i << ", column " << j);
            CHECK(J[i * n + j] == Approx(numeric[i * n + j]).epsilon(1e-6).margin(1e-7 * row));
        }
    }
}

// J θ'' = −k θ on one node to ground.
NetworkSpec oscillator(double k) {
    NetworkSpec spec;
    spec.nodes.push_back(NodeSpec{"mass", Field::value(1.0), false});
    spec.spring_dampers.push_back(SpringDamperSpec{"spring", 0, kGround, Field::value(k), Field::value(0.0)});
    spec.outputs.push_back(OutputSpec{"angle", OutputKind::angle, 0, {}, Field::value(0.0)});
    return spec;
}

// Two unit inertias joined by a spring k, the first driven by the torque a·u(t).
NetworkSpec two_masses(double k, double a) {
    NetworkSpec spec;
    spec.input_names = {"T"};
    spec.nodes.push_back(NodeSpec{"driven", Field::value(1.0), false});
    spec.nodes.push_back(NodeSpec{"free", Field::value(1.0), false});
    spec.spring_dampers.push_back(SpringDamperSpec{"shaft", 0, 1, Field::value(k), Field::value(0.0)});
    spec.torques.push_back(TorqueSpec{"drive", 0, 0, Field::value(0.0), Field::value(a)});
    return spec;
}

// Samples t_i = i·t_end/intervals with the input u = t (a ramp) or no input.
InputChannels uniform_time(double t_end, std::size_t intervals, bool ramp) {
    std::vector<double> t(intervals + 1);
    for (std::size_t i = 0; i <= intervals; ++i) t[i] = t_end * static_cast<double>(i) / static_cast<double>(intervals);
    return ramp ? InputChannels(t, {t}) : InputChannels(t, {});
}

SimulationSettings rosenbrock(double rtol, double atol) {
    SimulationSettings s;
    s.method = IntegrationMethod::rosenbrock4;
    s.rtol = rtol;
    s.atol = atol;
    return s;
}

const auto keep_going = [](std::size_t, const std::vector<double>&, const std::vector<double>&) { return true; };

}  // namespace

TEST_CASE("rosenbrock4's Jacobian is the right-hand side's, by dual numbers", "[rosenbrock]") {
    SECTION("engine block: slider-crank throws on measured pressures") {
        const PresetConstants engine = {{"bore", {0.079}}, {"crank_radius", {0.0405}}, {"rod_length", {0.129}},
                                        {"K21", {8.0e4}},  {"Kxx", {3.0e5}},           {"K32", {2.0e5}},
                                        {"p_atm", {101300.0}}};
        const NetworkSpec spec = build_preset("engine_block", engine);
        std::vector<double> angle, pressure;
        for (int i = 0; i <= 1440; ++i) {
            angle.push_back(i * 3.14159265358979 / 180.0 - 10.0);
            pressure.push_back(1e5 + 4e6 * std::exp(-std::pow(std::sin(0.5 * angle.back()), 2) * 20));
        }
        const CrankAngleChannels by_angle(angle, std::vector<std::vector<double>>(spec.cylinders.size(), pressure));
        const std::vector<double> p = {0.0045, 0.0012, 0.12, 0.45, 0.010, 0.020, 0.025, 2.5, 4.0, 1.5};
        NetworkModel<double> model(spec);
        model.set_crank_angle_inputs(&by_angle);
        model.set_parameters(p.data());
        CHECK(model.parameters() == p);
        const std::size_t n = spec.nodes.size();
        std::vector<double> x(2 * n);
        for (std::size_t i = 0; i < n; ++i) {
            x[i] = 1.1 + 0.003 * static_cast<double>(i);
            x[n + i] = 130.0 - 0.4 * static_cast<double>(i);
        }
        check_jacobian(model, x, nullptr);
    }
    SECTION("CVT clearance: inside the smoothed impact zone") {
        const NetworkSpec spec = build_preset("cvt_clearance", {});
        const std::vector<double> p = {1.43, 2948, 8700, 4.1, 19.2, 0.0036, 1133, -7.4, 13.0};
        NetworkModel<double> model(spec);
        model.set_parameters(p.data());
        const double u = 25.0;
        for (double twist : {-0.004, 0.0, 0.0017, 0.006}) check_jacobian(model, {twist, 3.0}, &u);
    }
    SECTION("a chain of 20 inertias: 40 states, seeded in two chunks") {
        NetworkSpec spec;
        spec.parameter_names = {"k"};
        for (int i = 0; i < 20; ++i) {
            spec.nodes.push_back(NodeSpec{"n" + std::to_string(i), Field::value(0.01 * (1 + i % 3)), false});
            spec.spring_dampers.push_back(SpringDamperSpec{"s" + std::to_string(i), i, i == 0 ? kGround : i - 1,
                                                           Field::param(0), Field::value(0.3 + 0.1 * i)});
        }
        spec.clearances.push_back(ClearanceSpec{"stop", 19, 0, Field::value(100), Field::value(300), Field::value(1),
                                                Field::value(2), Field::value(0.01), Field::value(800), true});
        const double k = 5.0e3;
        NetworkModel<double> model(spec);
        model.set_parameters(&k);
        std::vector<double> x(40);
        for (std::size_t i = 0; i < 40; ++i) x[i] = 0.01 * std::sin(1.7 * static_cast<double>(i)) * (i < 20 ? 1.0 : 30.0);
        check_jacobian(model, x, nullptr);
    }
}

TEST_CASE("rosenbrock4's time derivative is the slope of the interpolated inputs", "[rosenbrock]") {
    // u: 0 → 10 over [0, 1] s, then 10 → 50 over [1, 3] s, driving a torque of 3·u.
    const NetworkSpec spec = two_masses(400.0, 3.0);
    NetworkModel<double> model(spec);
    model.set_parameters(nullptr);
    const InputChannels in({0.0, 1.0, 3.0}, {{0.0, 10.0, 50.0}});
    StiffBuffers buffers;
    std::vector<double> u;
    StiffNetworkSystem system(model, in, u, buffers);
    UblasVector x(4);
    const double state[] = {0.02, -0.01, 1.5, -0.5};
    std::copy(state, state + 4, x.begin());
    UblasMatrix J(4, 4);
    UblasVector dfdt(4), fp(4), fm(4);
    for (std::size_t interval : {0u, 1u}) {
        system.enter_interval(interval);
        const double t = interval == 0 ? 0.4 : 2.2, dt = 1e-3;
        system.jacobian(x, J, t, dfdt);
        system.rhs(x, fp, t + dt);
        system.rhs(x, fm, t - dt);
        for (std::size_t i = 0; i < 4; ++i) CHECK(dfdt[i] == Approx((fp[i] - fm[i]) / (2 * dt)).margin(1e-9));
        CHECK(dfdt[2] == Approx(interval == 0 ? 30.0 : 60.0));  // ∂ω0'/∂t = 3 · du/dt
        CHECK(system.start_finite());
    }
    // A held input: ∂f/∂t = 0 without evaluating f.
    const InputChannels held({0.0, 1.0}, {{7.0, 7.0}});
    StiffNetworkSystem still(model, held, u, buffers);
    still.enter_interval(0);
    still.jacobian(x, J, 0.5, dfdt);
    for (std::size_t i = 0; i < 4; ++i) CHECK(dfdt[i] == 0.0);
    CHECK(J(2, 0) == -400.0);  // ∂ω0'/∂θ0 = −k/J
    CHECK(J(2, 1) == 400.0);
    CHECK(J(0, 2) == 1.0);     // ∂θ0'/∂ω0
}

TEST_CASE("the Rosenbrock stepper is exact on y' = t and y' = t² in one step", "[rosenbrock]") {
    // Order conditions that involve ∂f/∂t: odeint's own coefficients (γ4 = +0.0362) give
    // 0.834 instead of 0.8 for y' = t over [0.3, 1.3].
    for (int power : {0, 1, 2}) {
        Rosenbrock4 stepper;
        UblasVector y(1), error(1);
        y[0] = 0.0;
        auto system = std::make_pair(
            [power](const UblasVector&, UblasVector& dydt, double t) { dydt[0] = std::pow(t, power); },
            [power](const UblasVector&, UblasMatrix& J, double t, UblasVector& dfdt) {
                J(0, 0) = 0.0;
                dfdt[0] = power == 0 ? 0.0 : power * std::pow(t, power - 1);
            });
        stepper.do_step(system, y, 0.3, 1.0, error);
        INFO("y' = t^" << power);
        CHECK(y[0] == Approx((std::pow(1.3, power + 1) - std::pow(0.3, power + 1)) / (power + 1)).epsilon(1e-13));
    }
}

TEST_CASE("rosenbrock4 follows the exact solution of a ramp-driven two-mass network", "[rosenbrock]") {
    // θ1'' = −k(θ1 − θ2) + a·t, θ2'' = k(θ1 − θ2), unit inertias, from θ1 = −θ2 = q0/2 at rest.
    // Mean angle: a t³/12. Twist q = θ1 − θ2: q'' = −2k q + a t, so with ω = √(2k)
    // q = q0 cos ωt + a t/(2k) − a/(2kω) sin ωt.
    const double k = 5.0e3, a = 2.0, q0 = 0.02, t_end = 0.5, w = std::sqrt(2 * k);
    const std::size_t intervals = 500;
    const NetworkSpec spec = two_masses(k, a);
    NetworkModel<double> model(spec);
    model.set_parameters(nullptr);
    const InputChannels in = uniform_time(t_end, intervals, true);
    auto exact = [&](double t, double out[2]) {
        const double mean = a * t * t * t / 12.0;
        const double q = q0 * std::cos(w * t) + a * t / (2 * k) - a / (2 * k * w) * std::sin(w * t);
        out[0] = mean + 0.5 * q;
        out[1] = mean - 0.5 * q;
    };
    auto worst_error = [&](const SimulationSettings& settings, std::vector<std::vector<double>>* states = nullptr) {
        SimulationBuffers buffers;
        std::vector<double> x{0.5 * q0, -0.5 * q0, 0.0, 0.0};
        double worst = 0.0;
        const auto status = simulate_samples(model, in, 0, intervals, x, settings, buffers,
                                             [&](std::size_t i, const std::vector<double>& xi, const std::vector<double>&) {
                                                 double e[2];
                                                 exact(in.time()[i], e);
                                                 worst = std::max({worst, std::abs(xi[0] - e[0]), std::abs(xi[1] - e[1])});
                                                 if (states) states->push_back(xi);
                                                 return true;
                                             });
        REQUIRE(status == SimulationStatus::ok);
        if (settings.method == IntegrationMethod::rosenbrock4) CHECK(buffers.jacobian_evaluations > 0);
        CHECK(buffers.rhs_evaluations > 0);
        return worst;
    };
    CHECK(worst_error(rosenbrock(1e-10, 1e-12)) < 1e-8);  // against q0 = 0.02
    CHECK(worst_error(rosenbrock(1e-5, 1e-7)) < 1e-4);
    // And sample by sample against dopri5 at a tight tolerance.
    std::vector<std::vector<double>> stiff, explicit_rk;
    SimulationSettings dopri5;
    dopri5.method = IntegrationMethod::dopri5;
    dopri5.rtol = dopri5.atol = 1e-12;
    worst_error(rosenbrock(1e-10, 1e-12), &stiff);
    worst_error(dopri5, &explicit_rk);
    REQUIRE(stiff.size() == explicit_rk.size());
    for (std::size_t i = 0; i < stiff.size(); ++i)
        for (std::size_t j = 0; j < 4; ++j) CHECK(stiff[i][j] == Approx(explicit_rk[i][j]).margin(1e-8));
}

TEST_CASE("rosenbrock4 on a very stiff spring takes steps the accuracy asks for, not the stiffness", "[rosenbrock]") {
    // A critically damped stiff mode (k = 1e8, c = 2e4: λ = −1e4, double) dies out within
    // milliseconds; an explicit method stays bound to steps below ~3/|λ| for the whole second,
    // rosenbrock4 (L-stable) is not.
    NetworkSpec spec = oscillator(1e8);
    spec.spring_dampers[0].c = Field::value(2.0e4);
    NetworkModel<double> model(spec);
    model.set_parameters(nullptr);
    const InputChannels in = uniform_time(1.0, 100, false);
    SimulationBuffers buffers;
    std::vector<double> x{1e-3, 0.0};
    SimulationSettings s = rosenbrock(1e-6, 1e-9);
    s.max_steps = 2000;  // an explicit method would need ~1e4 steps here
    REQUIRE(simulate_samples(model, in, 0, 100, x, s, buffers, keep_going) == SimulationStatus::ok);
    CHECK(std::abs(x[0]) < 1e-9);
    CHECK(std::abs(x[1]) < 1e-6);
}

TEST_CASE("rosenbrock4 reports a failing simulation with a status", "[rosenbrock]") {
    const InputChannels in = uniform_time(10.0, 1000, false);
    SimulationBuffers buffers;
    SECTION("NaN parameters: not finite") {
        const NetworkSpec spec = oscillator(std::nan(""));
        NetworkModel<double> model(spec);
        model.set_parameters(nullptr);
        std::vector<double> x{1.0, 0.0};
        CHECK(simulate_samples(model, in, 0, 10, x, rosenbrock(1e-6, 1e-8), buffers, keep_going) ==
              SimulationStatus::not_finite);
    }
    SECTION("negative stiffness: diverged") {
        const NetworkSpec spec = oscillator(-4.0e4);
        NetworkModel<double> model(spec);
        model.set_parameters(nullptr);
        std::vector<double> x{1.0, 0.0};
        CHECK(simulate_samples(model, in, 0, 1000, x, rosenbrock(1e-6, 1e-8), buffers, keep_going) ==
              SimulationStatus::diverged);
    }
    SECTION("a step budget below one step per sample: step budget exceeded") {
        const NetworkSpec spec = oscillator(1e4);
        NetworkModel<double> model(spec);
        model.set_parameters(nullptr);
        std::vector<double> x{1.0, 0.0};
        SimulationSettings s = rosenbrock(1e-6, 1e-8);
        s.max_steps = 20;
        CHECK(simulate_samples(model, in, 0, 1000, x, s, buffers, keep_going) ==
              SimulationStatus::step_budget_exceeded);
    }
    SECTION("an observer that stops it: stopped") {
        const NetworkSpec spec = oscillator(1e4);
        NetworkModel<double> model(spec);
        model.set_parameters(nullptr);
        std::vector<double> x{1.0, 0.0};
        const auto stop_at_5 = [](std::size_t i, const std::vector<double>&, const std::vector<double>&) { return i < 5; };
        CHECK(simulate_samples(model, in, 0, 1000, x, rosenbrock(1e-6, 1e-8), buffers, stop_at_5) ==
              SimulationStatus::stopped_by_observer);
    }
}

TEST_CASE("the experiment file accepts simulation.method: rosenbrock4", "[rosenbrock][experiment]") {
    const std::filesystem::path config = test::source_dir() / "configs/cvt_tipin_clean.yaml";
    std::string text = test::read_text(config);
    const std::string shipped = "simulation: { method: rk4, step: sample }";
    const std::string data = "file: ../data/cvt/tipin_clean.csv";
    REQUIRE(text.find(shipped) != std::string::npos);
    REQUIRE(text.find(data) != std::string::npos);
    text.replace(text.find(data), data.size(), "file: " + (test::source_dir() / "data/cvt/tipin_clean.csv").string());
    const test::TempDir dir;
    auto with_simulation = [&](const std::string& line) {
        std::string t = text;
        t.replace(t.find(shipped), shipped.size(), line);
        return dir.write("exp.yaml", t);
    };

    const Experiment ex = load_experiment(with_simulation("simulation: { method: rosenbrock4, rtol: 1.0e-7, atol: 1.0e-9, max_steps: 5000 }"));
    CHECK(ex.simulation.method == IntegrationMethod::rosenbrock4);
    CHECK(ex.simulation.rtol == 1e-7);
    CHECK(ex.simulation.atol == 1e-9);
    CHECK(ex.simulation.max_steps == 5000);
    CHECK(load_experiment(config, {parse_override("simulation.method=rosenbrock4")}).simulation.method ==
          IntegrationMethod::rosenbrock4);

    // An unknown name is refused with the file, line, key and the valid names.
    const auto file = with_simulation("simulation: { method: radau5 }");
    try {
        (void)load_experiment(file);
        FAIL("loaded an unknown integration method");
    } catch (const InputError& e) {
        CHECK(e.key() == "simulation.method");
        CHECK(std::string(e.what()).find("'radau5' is not one of: rk4, dopri5, rosenbrock4") != std::string::npos);
        CHECK(std::string(e.what()).rfind(file.string() + ":", 0) == 0);
    }
}

}  // namespace TVID_UNITY_ID

// The fixed-step implicit method sdirk3 (sim/sdirk3.hpp): its third order on a ramp-driven
// two-mass network with a known solution; its L-stability on a spring far stiffer than
// its step; its sensitivities, the exact derivatives of its discrete steps, against
// differences of simulations with a stiff dry friction; its failure statuses; and
// `simulation.method: sdirk3` in the experiment file.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <vector>

#include "support/test_files.hpp"
#include "tvid/experiment/experiment.hpp"
#include "tvid/sim/sdirk3.hpp"
#include "tvid/sim/simulate.hpp"

namespace TVID_UNITY_ID {  // unique to this file in a unity build (tests/CMakeLists.txt)

using namespace tvid;

namespace {

// Two unit inertias joined by a spring k (parameter 0), the first driven by the torque a·u(t).
NetworkSpec two_masses(double a) {
    NetworkSpec spec;
    spec.parameter_names = {"k"};
    spec.input_names = {"T"};
    spec.nodes.push_back(NodeSpec{"driven", Field::value(1.0), false});
    spec.nodes.push_back(NodeSpec{"free", Field::value(1.0), false});
    spec.spring_dampers.push_back(SpringDamperSpec{"shaft", 0, 1, Field::param(0), Field::value(0.0)});
    spec.torques.push_back(TorqueSpec{"drive", 0, 0, Field::value(0.0), Field::value(a)});
    return spec;
}

InputChannels uniform_time(double t_end, std::size_t intervals, bool ramp) {
    std::vector<double> t(intervals + 1);
    for (std::size_t i = 0; i <= intervals; ++i) t[i] = t_end * static_cast<double>(i) / static_cast<double>(intervals);
    return ramp ? InputChannels(t, {t}) : InputChannels(t, {});
}

SimulationSettings sdirk3(double step = 0.0) {
    SimulationSettings s;
    s.method = IntegrationMethod::sdirk3;
    s.max_step = step;
    return s;
}

const auto keep_going = [](std::size_t, const std::vector<double>&, const std::vector<double>&) { return true; };

// The states at every sample of a plain sdirk3 simulation.
std::vector<std::vector<double>> trajectory(NetworkModel<double>& model, const InputChannels& in,
                                            std::vector<double> x, const SimulationSettings& s) {
    SimulationBuffers buffers;
    std::vector<std::vector<double>> out;
    const auto status = simulate_samples(model, in, 0, in.time().size() - 1, x, s, buffers,
                                         [&](std::size_t, const std::vector<double>& xi, const std::vector<double>&) {
                                             out.push_back(xi);
                                             return true;
                                         });
    REQUIRE(status == SimulationStatus::ok);
    return out;
}

}  // namespace

TEST_CASE("sdirk3 converges with the third order on a ramp-driven two-mass network", "[sdirk3]") {
    // θ1'' = −k(θ1 − θ2) + a·t, θ2'' = k(θ1 − θ2), from θ1 = −θ2 = q0/2 at rest: the mean angle
    // a t³/12, the twist q = q0 cos ωt + a t/(2k) − a/(2kω) sin ωt with ω = √(2k).
    const double k = 200.0, a = 2.0, q0 = 0.02, t_end = 1.0, w = std::sqrt(2 * k);
    const NetworkSpec spec = two_masses(a);
    NetworkModel<double> model(spec);
    model.set_parameters(&k);
    const auto worst_error = [&](std::size_t intervals) {
        const InputChannels in = uniform_time(t_end, intervals, true);
        const auto states = trajectory(model, in, {0.5 * q0, -0.5 * q0, 0.0, 0.0}, sdirk3());
        double worst = 0.0;
        for (std::size_t i = 0; i < states.size(); ++i) {
            const double t = in.time()[i + 1];
            const double q = q0 * std::cos(w * t) + a * t / (2 * k) - a / (2 * k * w) * std::sin(w * t);
            worst = std::max(worst, std::abs(states[i][0] - states[i][1] - q));
        }
        return worst;
    };
    const double coarse = worst_error(200), fine = worst_error(400);
    INFO("worst twist error: " << coarse << " at h = 5 ms, " << fine << " at 2.5 ms");
    CHECK(coarse < 2e-4);                  // against q0 = 0.02
    CHECK(coarse / fine > 6.5);            // 2³ = 8 for the third order
    CHECK(coarse / fine < 10.0);
}

TEST_CASE("sdirk3 steps a spring far stiffer than its step at the sample interval", "[sdirk3]") {
    // A critically damped mode λ = −1e4 1/s (k = 1e8, c = 2e4 on a unit inertia) at h = 10 ms:
    // hλ = −100, far outside any explicit method's region. L-stable: gone after one step.
    NetworkSpec spec;
    spec.nodes.push_back(NodeSpec{"mass", Field::value(1.0), false});
    spec.spring_dampers.push_back(SpringDamperSpec{"spring", 0, kGround, Field::value(1e8), Field::value(2e4)});
    NetworkModel<double> model(spec);
    model.set_parameters(nullptr);
    const InputChannels in = uniform_time(1.0, 100, false);
    SimulationBuffers buffers;
    std::vector<double> x{1e-3, 0.0};
    REQUIRE(simulate_samples(model, in, 0, 100, x, sdirk3(), buffers, keep_going) == SimulationStatus::ok);
    CHECK(std::abs(x[0]) < 1e-12);
    CHECK(std::abs(x[1]) < 1e-9);
    CHECK(buffers.sdirk3.steps == 100);  // one step per sample, none halved
    CHECK(buffers.sdirk3.halvings == 0);
    CHECK(buffers.jacobian_evaluations > 0);
    CHECK(buffers.jacobian_evaluations < 100);  // the Jacobian is kept while Newton converges fast
}

TEST_CASE("sdirk3's sensitivities are the derivatives of its steps, through a stiff dry friction", "[sdirk3]") {
    // The two masses with a Coulomb friction of 0.5 N m between them smoothed over 0.01 rad/s:
    // sticking, its slope 0.5/0.01 on two unit inertias is a real mode near −100 1/s, and the
    // relative speed crosses zero, sticks and slips within the 0.5 s at 5 ms steps. (The
    // differences' step is small: at 1e-4·k their truncation error alone is 2e-5 relative.)
    NetworkSpec spec = two_masses(40.0);
    FrictionSpec friction;
    friction.name = "slip";
    friction.a = 0;
    friction.b = 1;
    friction.coulomb = Field::value(0.5);
    friction.smoothing_speed = Field::value(0.01);
    friction.smoothing_given = true;
    friction.dry = true;
    spec.frictions.push_back(friction);
    const double k = 300.0;
    const InputChannels in = uniform_time(0.5, 100, true);
    const std::vector<double> x0{0.01, -0.01, 0.0, 0.0};

    // S = ∂x/∂k from the stepper with the dual model seeded along k.
    NetworkModel<double> model(spec);
    model.set_parameters(&k);
    NetworkModel<Dual> dual(spec);
    const Dual k_seeded = Dual::variable(k, 0, 1);
    dual.set_parameters(&k_seeded);
    std::vector<Dual> xd(4), fd(4);
    Sdirk3 stepper;
    stepper.bind(model, in);
    stepper.bind_sensitivities(dual, 1, xd, fd);
    std::vector<double> x = x0, s(4, 0.0);
    stepper.begin(x.data());
    std::vector<std::vector<double>> sensitivities;
    for (std::size_t i = 0; i + 1 < in.time().size(); ++i) {
        REQUIRE(stepper.cross(in.time(), i, 0.0, x.data(), s.data()) == SimulationStatus::ok);
        sensitivities.push_back(s);
    }
    CHECK(stepper.halvings == 0);

    // Central differences of plain simulations.
    const double dk = 1e-6 * k;
    NetworkModel<double> up(spec), down(spec);
    const double k_up = k + dk, k_down = k - dk;
    up.set_parameters(&k_up);
    down.set_parameters(&k_down);
    const auto plus = trajectory(up, in, x0, sdirk3()), minus = trajectory(down, in, x0, sdirk3());
    REQUIRE(plus.size() == sensitivities.size());
    double largest = 0.0;
    for (const auto& row : sensitivities)
        for (double v : row) largest = std::max(largest, std::abs(v));
    REQUIRE(largest > 1e-6);
    for (std::size_t i = 0; i < sensitivities.size(); ++i)
        for (std::size_t j = 0; j < 4; ++j) {
            INFO("sample " << i + 1 << ", state " << j);
            CHECK(sensitivities[i][j] == Approx((plus[i][j] - minus[i][j]) / (2 * dk)).margin(1e-5 * largest));
        }
}

TEST_CASE("sdirk3 reports a failing simulation with a status", "[sdirk3]") {
    const InputChannels in = uniform_time(10.0, 1000, false);
    SimulationBuffers buffers;
    NetworkSpec spec;
    spec.nodes.push_back(NodeSpec{"mass", Field::value(1.0), false});
    spec.spring_dampers.push_back(SpringDamperSpec{"spring", 0, kGround, Field::param(0), Field::value(0.0)});
    spec.parameter_names = {"k"};
    NetworkModel<double> model(spec);
    std::vector<double> x{1.0, 0.0};
    SECTION("NaN stiffness: not finite") {
        const double k = std::nan("");
        model.set_parameters(&k);
        CHECK(simulate_samples(model, in, 0, 10, x, sdirk3(), buffers, keep_going) == SimulationStatus::not_finite);
    }
    SECTION("negative stiffness: diverged") {
        const double k = -4.0e2;
        model.set_parameters(&k);
        CHECK(simulate_samples(model, in, 0, 1000, x, sdirk3(), buffers, keep_going) == SimulationStatus::diverged);
    }
}

TEST_CASE("the experiment file accepts simulation.method: sdirk3", "[sdirk3][experiment]") {
    const std::filesystem::path config = test::source_dir() / "configs/driveline_clean.yaml";
    const Experiment ex = load_experiment(config, {parse_override("simulation.method=sdirk3"),
                                                   parse_override("simulation.step=sample")});
    CHECK(ex.simulation.method == IntegrationMethod::sdirk3);
    CHECK(ex.simulation.max_step == 0.0);
}

}  // namespace TVID_UNITY_ID

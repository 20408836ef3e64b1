// Boost.Odeint integration of a network: RK4 order, dopri5 accuracy, input
// interpolation, and failure statuses instead of crashes.
#include <catch2/catch.hpp>
#include <cmath>

#include "tvid/sim/simulate.hpp"

namespace TVID_UNITY_ID {  // unique to this file in a unity build (tests/CMakeLists.txt)

using namespace tvid;

namespace {

// Undamped oscillator J θ'' = −k θ with θ(0) = θ0, θ'(0) = 0: θ(t) = θ0 cos(√(k/J) t).
NetworkSpec oscillator(double k) {
    NetworkSpec spec;
    spec.nodes.push_back(NodeSpec{"mass", Field::value(1.0), false});
    spec.spring_dampers.push_back(SpringDamperSpec{"spring", 0, kGround, Field::value(k), Field::value(0.0)});
    spec.outputs.push_back(OutputSpec{"angle", OutputKind::angle, 0, {}, Field::value(0.0)});
    return spec;
}

InputChannels uniform_time(double t_end, std::size_t intervals) {
    std::vector<double> t(intervals + 1);
    for (std::size_t i = 0; i <= intervals; ++i) t[i] = t_end * static_cast<double>(i) / static_cast<double>(intervals);
    return InputChannels(t, {});
}

double final_error(const SimulationSettings& settings, std::size_t intervals) {
    const double k = 400.0, theta0 = 0.1, t_end = 1.0;  // ω = 20 rad/s
    const NetworkSpec spec = oscillator(k);
    NetworkModel<double> model(spec);
    model.set_parameters(nullptr);
    const InputChannels in = uniform_time(t_end, intervals);
    SimulationBuffers buffers;
    std::vector<double> x{theta0, 0.0};
    std::size_t seen = 0;
    const auto status = simulate_samples(model, in, 0, intervals, x, settings, buffers,
                                         [&](std::size_t, const std::vector<double>&, const std::vector<double>&) {
                                             ++seen;
                                             return true;
                                         });
    REQUIRE(status == SimulationStatus::ok);
    REQUIRE(seen == intervals);
    return std::abs(x[0] - theta0 * std::cos(20.0 * t_end));
}

}  // namespace

TEST_CASE("RK4 at the sampling interval converges with order 4", "[simulate]") {
    SimulationSettings rk4;
    const double e1 = final_error(rk4, 100), e2 = final_error(rk4, 200), e3 = final_error(rk4, 400);
    // Halving the step divides the error by 2^4 = 16.
    CHECK(e1 / e2 == Approx(16.0).epsilon(0.1));
    CHECK(e2 / e3 == Approx(16.0).epsilon(0.1));
    // Substeps (step: 0.0025 s on 10 ms samples) give the accuracy of the finer grid.
    SimulationSettings fine;
    fine.max_step = 0.0025;
    CHECK(final_error(fine, 100) == Approx(e3).epsilon(1e-6));
}

TEST_CASE("dopri5 meets its tolerance", "[simulate]") {
    SimulationSettings s;
    s.method = IntegrationMethod::dopri5;
    s.rtol = 1e-10;
    s.atol = 1e-12;
    CHECK(final_error(s, 50) < 1e-8);
    s.rtol = 1e-4;
    s.atol = 1e-6;
    CHECK(final_error(s, 50) < 1e-3);
}

TEST_CASE("inputs are interpolated linearly between samples", "[simulate]") {
    const InputChannels in({0.0, 1.0, 3.0}, {{0.0, 10.0, 30.0}, {5.0, 5.0, -5.0}});
    std::size_t hint = 0;
    double u[2];
    in.at(0.5, hint, u);
    CHECK(u[0] == 5.0);
    CHECK(u[1] == 5.0);
    in.at(2.0, hint, u);
    CHECK(u[0] == 20.0);
    CHECK(u[1] == 0.0);
    CHECK(hint == 1);
    in.at(0.25, hint, u);  // going back in time still works
    CHECK(u[0] == 2.5);
    in.at(-1.0, hint, u);  // before the recording: the first value is held
    CHECK(u[0] == 0.0);
    in.at(9.0, hint, u);
    CHECK(u[1] == -5.0);
}

TEST_CASE("a simulation that blows up returns a status instead of crashing", "[simulate]") {
    // Negative stiffness: exponential growth beyond the divergence limit.
    const NetworkSpec spec = oscillator(-4.0e4);
    NetworkModel<double> model(spec);
    model.set_parameters(nullptr);
    const InputChannels in = uniform_time(10.0, 1000);
    SimulationBuffers buffers;
    std::vector<double> x{1.0, 0.0};
    const auto ok = [](std::size_t, const std::vector<double>&, const std::vector<double>&) { return true; };
    const auto status = simulate_samples(model, in, 0, 1000, x, SimulationSettings{}, buffers, ok);
    CHECK((status == SimulationStatus::diverged || status == SimulationStatus::not_finite));

    SimulationSettings budget;
    budget.method = IntegrationMethod::dopri5;
    budget.max_steps = 20;
    std::vector<double> y{1.0, 0.0};
    const NetworkSpec stiff = oscillator(1e8);
    NetworkModel<double> stiff_model(stiff);
    stiff_model.set_parameters(nullptr);
    CHECK(simulate_samples(stiff_model, in, 0, 1000, y, budget, buffers, ok) == SimulationStatus::step_budget_exceeded);

    // NaN parameters give NaN states: not finite.
    const NetworkSpec nan_spec = oscillator(std::nan(""));
    NetworkModel<double> nan_model(nan_spec);
    nan_model.set_parameters(nullptr);
    std::vector<double> z{1.0, 0.0};
    CHECK(simulate_samples(nan_model, in, 0, 10, z, SimulationSettings{}, buffers, ok) == SimulationStatus::not_finite);
}

}  // namespace TVID_UNITY_ID

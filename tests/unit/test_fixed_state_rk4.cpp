// RK4 over a fixed-size state (simulate_samples for small models) against odeint's
// runge_kutta4 over std::vector (march_samples with NetworkSystem): the same arithmetic,
// so bit-identical without inputs, and equal to rounding where the inputs' midpoints are
// precomputed instead of interpolated at t + h/2.
#include <catch2/catch.hpp>
#include <cmath>

#include "support/test_files.hpp"
#include "tvid/estimation/identification_problem.hpp"
#include "tvid/experiment/experiment.hpp"
#include "tvid/sim/simulate.hpp"

namespace TVID_UNITY_ID {  // unique to this file in a unity build (tests/CMakeLists.txt)

using namespace tvid;

namespace {

struct Trajectory {
    SimulationStatus status;
    std::vector<std::vector<double>> states;
    std::vector<std::vector<double>> inputs;
};

// The window's simulation from the experiment's initial state with both steppers.
std::pair<Trajectory, Trajectory> both_ways(const char* config, std::size_t max_samples) {
    const Experiment ex = load_experiment(test::source_dir() / "configs" / config);
    const IdentificationProblem problem(ex);
    auto ws = problem.make_workspace();
    ws->model.set_parameters(ws->params.data());
    const Window& w = ex.estimation.at(0);
    REQUIRE(problem.start_window(w, *ws, nullptr).status == SimulationStatus::ok);
    const std::size_t last = std::min(w.last, w.start + max_samples);
    const std::vector<double> x0 = ws->x_start;
    auto record = [](Trajectory& tr) {
        return [&tr](std::size_t, const std::vector<double>& x, const std::vector<double>& u) {
            tr.states.push_back(x);
            tr.inputs.push_back(u);
            return true;
        };
    };
    Trajectory fixed, odeint;
    std::vector<double> x = x0;
    fixed.status = simulate_samples(ws->model, problem.inputs(), w.start, last, x, ex.simulation, ws->buffers,
                                    record(fixed));
    x = x0;
    NetworkSystem system(ws->model, problem.inputs(), ws->buffers.u);
    odeint.status = march_samples(system, problem.inputs(), w.start, last, x, x.size(), ex.simulation, ws->buffers,
                                  record(odeint));
    return {fixed, odeint};
}

}  // namespace

TEST_CASE("fixed-state RK4 is bit-identical to odeint's RK4 on the engine block (substeps, no time inputs)",
          "[simulate][rk4]") {
    const auto [fixed, odeint] = both_ways("engine_idle_clean.yaml", 400);
    REQUIRE(fixed.status == SimulationStatus::ok);
    REQUIRE(odeint.status == SimulationStatus::ok);
    REQUIRE(fixed.states.size() == 400);
    CHECK(fixed.states == odeint.states);
}

TEST_CASE("fixed-state RK4 equals odeint's RK4 to rounding on the CVT window (input midpoints precomputed)",
          "[simulate][rk4]") {
    const auto [fixed, odeint] = both_ways("cvt_tipin.yaml", 100000);
    REQUIRE(fixed.status == SimulationStatus::ok);
    REQUIRE(fixed.states.size() == odeint.states.size());
    REQUIRE(fixed.states.size() == 1500);
    CHECK(fixed.inputs == odeint.inputs);  // the observer sees the samples themselves
    double worst = 0;
    for (std::size_t k = 0; k < fixed.states.size(); ++k)
        for (std::size_t j = 0; j < 2; ++j)
            worst = std::max(worst, std::abs(fixed.states[k][j] - odeint.states[k][j]) /
                                        (std::abs(odeint.states[k][j]) + 1e-3));
    CHECK(worst < 1e-10);
}

}  // namespace TVID_UNITY_ID

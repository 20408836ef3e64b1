// The one sample loop (march_over_samples): the order of its hooks, and the two ways of
// crossing an interval.
#include <catch2/catch.hpp>

#include <string>
#include <vector>

#include "tvid/sim/observation_loops.hpp"

namespace TVID_UNITY_ID {  // unique to this file in a unity build (tests/CMakeLists.txt)

using namespace tvid;

namespace {

/// Hooks that write down what the loop asks of them: "b0" at the start, "aI" at sample I.
struct Diary {
    std::string& log;
    std::size_t stop_at = static_cast<std::size_t>(-1);
    void begin(std::size_t i) { log += "b" + std::to_string(i) + " "; }
    SimulationStatus arrive(std::size_t i) {
        log += "a" + std::to_string(i) + " ";
        return i == stop_at ? SimulationStatus::stopped_by_observer : SimulationStatus::ok;
    }
};

}  // namespace

TEST_CASE("the sample loop begins once, then crosses each interval before arriving at its end", "[sim][march]") {
    const std::vector<double> time{0.0, 0.1, 0.2, 0.35, 0.5};
    std::string log;
    const auto cross = [&](std::size_t i) {
        log += "c" + std::to_string(i) + " ";
        return SimulationStatus::ok;
    };
    CHECK(march_over_samples(1, 4, cross, Diary{log}) == SimulationStatus::ok);
    CHECK(log == "b1 c1 a2 c2 a3 c3 a4 ");
    log.clear();
    CHECK(march_over_samples(0, 4, cross, Diary{log, 2}) == SimulationStatus::stopped_by_observer);
    CHECK(log == "b0 c0 a1 c1 a2 ");  // the observer's status ends the march
    log.clear();
    const auto fail_at_2 = [&](std::size_t i) {
        log += "c" + std::to_string(i) + " ";
        return i == 2 ? SimulationStatus::diverged : SimulationStatus::ok;
    };
    CHECK(march_over_samples(0, 4, fail_at_2, Diary{log}) == SimulationStatus::diverged);
    CHECK(log == "b0 c0 a1 c1 a2 c2 ");  // no arrival at a state that failed its check
}

TEST_CASE("fixed substeps split each interval equally and report the state's check", "[sim][march]") {
    const std::vector<double> time{0.0, 0.1, 0.25};
    std::vector<FixedStep> steps;
    int checks = 0;
    FixedSubsteps cross(
        time, 0.05, [&](const FixedStep& s) { steps.push_back(s); },
        [&] { return ++checks == 2 ? SimulationStatus::not_finite : SimulationStatus::ok; });
    CHECK(cross(0) == SimulationStatus::ok);
    REQUIRE(steps.size() == 2);
    CHECK(steps[1].substep == 1);
    CHECK(steps[1].t == Approx(0.05));
    CHECK(steps[1].dt == Approx(0.05));
    CHECK(cross(1) == SimulationStatus::not_finite);
    REQUIRE(steps.size() == 5);  // 0.15 s in three steps of 0.05 s
    CHECK(steps[4].sample == 1);
    CHECK(steps[4].substeps == 3);
    CHECK(steps[4].t + steps[4].dt == Approx(0.25));
}

TEST_CASE("controlled steps end exactly on each sample and keep to their budget", "[sim][march]") {
    const std::vector<double> time{0.0, 1.0, 1.5, 4.0};
    std::vector<std::size_t> entered;
    std::vector<double> reached;
    // A stepper that accepts steps up to 0.4 s and rejects longer ones (halving them).
    const auto try_step = [&](double& t, double& dt) {
        StepAttempt attempt;
        if (dt > 0.4) {
            dt *= 0.5;
            return attempt;
        }
        t += dt;
        reached.push_back(t);
        attempt.accepted = true;
        return attempt;
    };
    ControlledSteps cross(time, 0, 3, 100, [&](std::size_t i) { entered.push_back(i); }, try_step);
    for (std::size_t i = 0; i < 3; ++i) {
        CHECK(cross(i) == SimulationStatus::ok);
        CHECK(reached.back() == time[i + 1]);  // no rounding short of the sample
    }
    CHECK(entered == std::vector<std::size_t>{0, 1, 2});
    // The budget counts attempts over the whole march.
    ControlledSteps tight(time, 0, 3, 4, [](std::size_t) {}, try_step);
    CHECK(tight(0) == SimulationStatus::step_budget_exceeded);  // 1 s: 2 rejections, then 4 steps of 0.25 s
}

}  // namespace TVID_UNITY_ID

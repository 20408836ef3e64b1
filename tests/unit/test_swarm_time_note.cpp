// What `tvid fit` says after the swarm's first iteration: the time its iterations will take
// at most, and with no optimizer given, the local alternative.
#include <catch2/catch.hpp>
#include <string>

#include "tvid/fit/swarm_time_note.hpp"

namespace TVID_UNITY_ID {  // unique to this file in a unity build (tests/CMakeLists.txt)

using namespace tvid;

namespace {

EstimationSettings swarm(OptimizerKind kind, bool given) {
    EstimationSettings s;
    s.optimizer = kind;
    s.optimizer_given = given;
    return s;
}

}  // namespace

TEST_CASE("the default swarm foretells its time from its first iteration and names lm", "[swarm]") {
    // The paper's swarm on a 9-parameter driveline: 512 particles scored in 51 s, 250 iterations more.
    const EstimationSettings s = swarm(OptimizerKind::pso, false);
    CHECK(s.pso.iterations == 250);
    CHECK(swarm_time_note(s, 9, 512, 51.0) ==
          "pso: scoring the 512 initial particles took 51 s; 250 iterations more will take at most about 3.5 h "
          "(the swarm is the default, as the experiment names no optimizer: `optimizer: lm` with `cost: l2` fits "
          "locally from the init values, each step one simulation with its 9 sensitivities)");
    EstimationSettings l2 = s;
    l2.cost = CostKind::l2;
    l2.jacobian = JacobianKind::fd;
    CHECK(swarm_time_note(l2, 4, 16, 2.0) ==
          "pso: scoring the 16 initial particles took 2 s; 250 iterations more will take at most about 8 min "
          "(the swarm is the default, as the experiment names no optimizer: `optimizer: lm` fits locally from the "
          "init values, each step one simulation with 2 × 4 more for its differences)");
}

TEST_CASE("a swarm the experiment names is foretold without advice, pso+lm with its polish", "[swarm]") {
    CHECK(swarm_time_note(swarm(OptimizerKind::pso, true), 9, 512, 51.0) ==
          "pso: scoring the 512 initial particles took 51 s; 250 iterations more will take at most about 3.5 h");
    EstimationSettings hybrid = swarm(OptimizerKind::pso_lm, true);
    hybrid.pso.iterations = 40;
    CHECK(swarm_time_note(hybrid, 3, 64, 3.2) ==
          "pso+lm: scoring the 64 initial particles took 3.2 s; 40 iterations more will take at most about 2 min, "
          "then LM polishes the best particle");
}

TEST_CASE("no word of a short swarm, nor of an optimizer without one", "[swarm]") {
    // 0.2 s + 250 × 0.2 s = 50.2 s: under a minute.
    CHECK(swarm_time_note(swarm(OptimizerKind::pso, false), 9, 512, 0.2).empty());
    CHECK_FALSE(swarm_time_note(swarm(OptimizerKind::pso, false), 9, 512, 0.25).empty());
    EstimationSettings none = swarm(OptimizerKind::pso, true);
    none.pso.iterations = 0;
    CHECK(swarm_time_note(none, 9, 512, 1000.0).empty());
    for (OptimizerKind kind : {OptimizerKind::lm, OptimizerKind::nlopt, OptimizerKind::multistart})
        CHECK(swarm_time_note(swarm(kind, true), 9, 1, 1000.0).empty());
}

TEST_CASE("durations read roughly, in the unit that fits", "[swarm]") {
    CHECK(rough_duration_text(0.84) == "0.84 s");
    CHECK(rough_duration_text(51.2) == "51 s");
    CHECK(rough_duration_text(720) == "12 min");
    CHECK(rough_duration_text(12750) == "3.5 h");
    CHECK(rough_duration_text(2.7468e6) == "763 h");
}

}  // namespace TVID_UNITY_ID

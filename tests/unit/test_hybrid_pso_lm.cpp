// pso+lm on a problem with many local minima: the swarm finds the basin, LM polishes to the
// exact optimum, and the history runs on continuously from one phase to the other.
#include <catch2/catch.hpp>
#include <cmath>

#include "support/sinusoid_fit.hpp"
#include "tvid/optim/hybrid_pso_lm.hpp"

namespace TVID_UNITY_ID {  // unique to this file in a unity build (tests/CMakeLists.txt)

using namespace tvid;
using tvid::test::SinusoidFit;

namespace {

const SearchBox kBox{{0.0, 0.1}, {10.0, 10.0}, {0.5, 0.5}, {3.0, 8.0}};

PsoSettings short_swarm() {
    PsoSettings s;
    s.start = PsoStart::latin_hypercube;
    s.particles = 24;
    s.iterations = 15;
    s.seed = 3;
    return s;
}

}  // namespace

TEST_CASE("pso+lm: the swarm's basin, then LM to the exact optimum", "[hybrid]") {
    SinusoidFit problem;
    // Neither phase alone: LM from the middle of the box stops in a local minimum, and the
    // short swarm ends near but not at the optimum.
    SinusoidFit lone;
    const LmSummary lm_only = run_levenberg_marquardt(LmSettings{}, {1.75, 4.25}, kBox.lower, kBox.upper, lone);
    CHECK(lm_only.best_cost > 1.0);

    const HybridSummary h = run_pso_then_lm(short_swarm(), LmSettings{}, kBox, problem, problem);
    REQUIRE(h.polished);
    CHECK(h.pso.best_cost > 1e-6);
    CHECK(h.best[0] == Approx(SinusoidFit::kAmplitude).epsilon(1e-9));
    CHECK(h.best[1] == Approx(SinusoidFit::kFrequency).epsilon(1e-9));
    CHECK(h.best_cost < 1e-18);
    CHECK(h.success);
    CHECK(h.termination == "swarm: iteration limit; lm: " + h.lm.termination);
    CHECK(h.termination_type == h.lm.termination_type);
    CHECK(h.iterations == h.pso.iterations + 1 + h.lm.iterations);
    CHECK(h.evaluations == problem.calls);  // swarm candidates + LM calls (the problem counts no simulations)
    // The LM start is the swarm's best particle.
    CHECK(h.lm.initial_cost == Approx(h.pso.best_cost).epsilon(1e-12));

    // History: swarm rows 0 … K, then the LM start as K + 1, numbered on; evaluations
    // cumulative and the best cost never rising.
    REQUIRE(h.history.size() == h.pso.history.size() + h.lm.history.size());
    for (std::size_t k = 0; k < h.history.size(); ++k) {
        CHECK(h.history[k].iteration == static_cast<int>(k));
        if (k == 0) continue;
        CHECK(h.history[k].evaluations >= h.history[k - 1].evaluations);
        CHECK(h.history[k].best_cost <= h.history[k - 1].best_cost);
    }
    CHECK(h.history.back().evaluations == h.evaluations);
    CHECK(h.history.back().best_cost == h.best_cost);
}

TEST_CASE("pso+lm: a stop during the swarm skips the polish", "[hybrid]") {
    SinusoidFit problem;
    int rows = 0;
    const HybridSummary h = run_pso_then_lm(short_swarm(), LmSettings{}, kBox, problem, problem,
                                            [&](const HistoryRow&) { return ++rows < 5; });
    CHECK_FALSE(h.polished);
    CHECK(h.termination == "stopped");
    CHECK(h.termination_type == TerminationType::stopped);
    CHECK(h.history.size() == 5);
    CHECK_FALSE(h.success);
}

TEST_CASE("pso+lm: a stop during the polish ends it", "[hybrid]") {
    SinusoidFit problem;
    const PsoSettings swarm = short_swarm();
    const HybridSummary h = run_pso_then_lm(swarm, LmSettings{}, kBox, problem, problem,
                                            [&](const HistoryRow& row) { return row.iteration < swarm.iterations + 3; });
    REQUIRE(h.polished);
    CHECK(h.lm.termination == "stopped");
    CHECK(h.termination == "stopped");
    CHECK(h.termination_type == TerminationType::stopped);
    CHECK(h.history.back().iteration == swarm.iterations + 3);
    CHECK_FALSE(h.success);
}

}  // namespace TVID_UNITY_ID

// The same experiment and seed give bit-identical results for 1 and 3 threads with the
// new optimizers: NLopt (single simulations, and gradients from sensitivity blocks split
// by thread), pso+lm, and multistart (starts run at once on their share of the threads).
// Only the count of simulations may differ: with RK4 a sensitivity Jacobian takes one
// column block per thread (1 + blocks simulations), each column the same whatever its block,
// and LM evaluates the trial steps of the next rejections side by side when it has threads.
#include <catch2/catch.hpp>

#include "support/test_files.hpp"
#include "tvid/experiment/experiment.hpp"
#include "tvid/fit/fit_run.hpp"

namespace TVID_UNITY_ID {  // unique to this file in a unity build (tests/CMakeLists.txt)

using namespace tvid;

namespace {

void check_same_for_1_and_3_threads(const std::vector<Override>& overrides, const char* name,
                                    bool same_simulations = false) {
    std::vector<Override> all = {{"estimation.cost", "l2"}};
    all.insert(all.end(), overrides.begin(), overrides.end());
    const Experiment ex = load_experiment(test::source_dir() / "configs/cvt_tipin_clean.yaml", all);
    const IdentificationProblem problem(ex);
    std::vector<FitResult> runs;
    for (int threads : {1, 3}) {
        FitOptions o;
        o.threads = threads;
        runs.push_back(run_fit(problem, o));
    }
    const OptimizerRun& a = runs[0].run;
    const OptimizerRun& b = runs[1].run;
    CHECK(a.name == name);
    CHECK(runs[1].threads == 3);
    CHECK(a.best == b.best);  // exact, not approximate
    CHECK(a.best_cost == b.best_cost);
    if (same_simulations) CHECK(a.evaluations == b.evaluations);
    CHECK(a.termination == b.termination);
    REQUIRE(a.history.size() == b.history.size());
    for (std::size_t k = 0; k < a.history.size(); ++k) {
        CHECK(a.history[k].best_cost == b.history[k].best_cost);
        CHECK(a.history[k].iteration == b.history[k].iteration);
        if (same_simulations) CHECK(a.history[k].evaluations == b.history[k].evaluations);
    }
}

}  // namespace

TEST_CASE("nlopt with the sensitivity gradient is bit-identical for 1 and 3 threads", "[nlopt][threads]") {
    check_same_for_1_and_3_threads(
        {{"estimation.optimizer", "nlopt"}, {"estimation.nlopt", "{ algorithm: LD_LBFGS, max_evaluations: 25 }"}},
        "nlopt");
}

TEST_CASE("a randomized nlopt algorithm is bit-identical for 1 and 3 threads", "[nlopt][threads][heavy]") {
    check_same_for_1_and_3_threads(
        {{"estimation.optimizer", "nlopt"},
         {"estimation.nlopt", "{ algorithm: GN_ISRES, max_evaluations: 150, seed: 3 }"},
         {"parameters.d_ds", "{ min: -20, max: 0 }"}},
        "nlopt", true);
}

TEST_CASE("pso+lm is bit-identical for 1 and 3 threads", "[hybrid][threads]") {
    check_same_for_1_and_3_threads({{"estimation.optimizer", "pso+lm"},
                                    {"estimation.pso", "{ start: latin_hypercube, particles: 16, iterations: 3 }"},
                                    {"estimation.lm.max_iterations", "5"}},
                                   "pso+lm");
}

TEST_CASE("multistart is bit-identical for 1 and 3 threads", "[multistart][threads]") {
    check_same_for_1_and_3_threads(
        {{"estimation.optimizer", "multistart"}, {"estimation.multistart", "{ starts: 4, max_iterations: 5 }"}},
        "multistart");  // the last starts running take up the cores the others left: more simulations side by side
}

}  // namespace TVID_UNITY_ID

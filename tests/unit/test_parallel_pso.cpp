// The swarm evaluated on several threads gives bit-identical results to one thread.
#include <catch2/catch.hpp>

#include "support/test_files.hpp"
#include "tvid/experiment/experiment.hpp"
#include "tvid/fit/fit_run.hpp"

namespace TVID_UNITY_ID {  // unique to this file in a unity build (tests/CMakeLists.txt)

using namespace tvid;

TEST_CASE("PSO on the CVT problem is bit-identical for 1, 2 and 3 threads", "[pso][threads]") {
    const Experiment ex = load_experiment(test::source_dir() / "configs/cvt_tipin.yaml",
                                          {{"estimation.pso.start", "latin_hypercube"},
                                           {"estimation.pso.particles", "24"},
                                           {"estimation.pso.iterations", "6"}});
    const IdentificationProblem problem(ex);
    std::vector<FitResult> runs;
    for (int threads : {1, 2, 3}) {
        FitOptions o;
        o.threads = threads;
        runs.push_back(run_fit(problem, o));
        CHECK(runs.back().threads == threads);
    }
    for (std::size_t r = 1; r < runs.size(); ++r) {
        CHECK(runs[r].run.best == runs[0].run.best);  // exact, not approximate
        CHECK(runs[r].run.best_cost == runs[0].run.best_cost);
        REQUIRE(runs[r].run.history.size() == runs[0].run.history.size());
        for (std::size_t k = 0; k < runs[0].run.history.size(); ++k) {
            CHECK(runs[r].run.history[k].best_cost == runs[0].run.history[k].best_cost);
            CHECK(runs[r].run.history[k].evaluations == runs[0].run.history[k].evaluations);
        }
    }
    // A different seed explores differently.
    FitOptions other;
    other.seed = 99;
    CHECK(run_fit(problem, other).run.best != runs[0].run.best);
}

}  // namespace TVID_UNITY_ID

// Judging a parameter vector on every window: the windows are simulated in parallel, and
// the evaluation is the same, bit for bit, whatever the number of threads.
#include <catch2/catch.hpp>

#include "support/test_files.hpp"
#include "tvid/analysis/evaluation.hpp"
#include "tvid/estimation/identification_problem.hpp"
#include "tvid/experiment/experiment.hpp"

namespace TVID_UNITY_ID {  // unique to this file in a unity build (tests/CMakeLists.txt)

using namespace tvid;
using tvid::test::source_dir;

namespace {

void require_same_split(const SplitEvaluation& a, const SplitEvaluation& b) {
    REQUIRE(a.windows.size() == b.windows.size());
    CHECK(a.ok == b.ok);
    for (std::size_t w = 0; w < a.windows.size(); ++w) {
        const WindowTrace& ta = a.windows[w].trace;
        const WindowTrace& tb = b.windows[w].trace;
        CHECK(ta.window == tb.window);
        CHECK(ta.samples == tb.samples);
        CHECK(ta.simulated == tb.simulated);
        CHECK(ta.measured == tb.measured);
    }
    REQUIRE(a.pooled.size() == b.pooled.size());
    for (std::size_t k = 0; k < a.pooled.size(); ++k) {
        CHECK(a.pooled[k].q_index == b.pooled[k].q_index);
        CHECK(a.pooled[k].rmse == b.pooled[k].rmse);
    }
}

}  // namespace

TEST_CASE("an evaluation on several threads equals the one-thread evaluation", "[evaluation]") {
    const Experiment ex = load_experiment(source_dir() / "configs/cvt_tipin_clean.yaml");
    const IdentificationProblem problem(ex);
    REQUIRE(ex.validation.size() >= 2);  // several windows to share out
    const std::vector<double> params = problem.full_parameters(problem.initial());

    const Evaluation one = evaluate_parameters(problem, params, 1);
    const Evaluation three = evaluate_parameters(problem, params, 3);
    CHECK(one.cost == three.cost);
    CHECK(one.cost > 0.0);
    CHECK(one.output_offsets == three.output_offsets);
    require_same_split(one.estimation, three.estimation);
    require_same_split(one.validation, three.validation);
    // The windows keep the experiment's order.
    for (std::size_t w = 0; w < ex.validation.size(); ++w)
        CHECK(three.validation.windows[w].trace.window == &ex.validation[w]);
}

}  // namespace TVID_UNITY_ID

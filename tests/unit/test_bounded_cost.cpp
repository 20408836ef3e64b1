// Stopping a candidate's simulation once its partial cost reaches its personal best:
// the cost with a bound never undercuts the bound unless it is the full cost, and the
// swarm takes exactly the same path with and without it, on any number of threads.
#include <catch2/catch.hpp>

#include <limits>

#include "support/test_files.hpp"
#include "tvid/estimation/identification_problem.hpp"
#include "tvid/estimation/parallel_evaluator.hpp"
#include "tvid/experiment/experiment.hpp"
#include "tvid/optim/pso.hpp"

namespace TVID_UNITY_ID {  // unique to this file in a unity build (tests/CMakeLists.txt)

using namespace tvid;

namespace {

// Forwards to an evaluator, with or without the bounds, and records every batch: the
// positions scored and the bounds the swarm passed (its personal-best costs).
class RecordingEvaluator : public CandidateEvaluator {
public:
    RecordingEvaluator(CandidateEvaluator& inner, bool use_bounds) : inner_(&inner), use_bounds_(use_bounds) {}
    void evaluate(const double* candidates, std::size_t count, std::size_t dimension, double* costs) override {
        inner_->evaluate(candidates, count, dimension, costs);
    }
    void evaluate_bounded(const double* candidates, std::size_t count, std::size_t dimension, const double* bounds,
                          double* costs) override {
        positions.insert(positions.end(), candidates, candidates + count * dimension);
        personal_bests.insert(personal_bests.end(), bounds, bounds + count);
        if (use_bounds_) inner_->evaluate_bounded(candidates, count, dimension, bounds, costs);
        else inner_->evaluate(candidates, count, dimension, costs);
    }
    std::vector<double> positions, personal_bests;

private:
    CandidateEvaluator* inner_;
    bool use_bounds_;
};

Experiment small_swarm_experiment(const char* config) {
    return load_experiment(test::source_dir() / "configs" / config, {{"estimation.pso.start", "latin_hypercube"},
                                                                      {"estimation.pso.particles", "24"},
                                                                      {"estimation.pso.iterations", "15"}});
}

SearchBox box_of(const IdentificationProblem& p) {
    return SearchBox{p.lower(), p.upper(), p.range_lower(), p.range_upper()};
}

}  // namespace

TEST_CASE("a cost with a bound is the full cost below the bound and a partial sum >= the bound above it",
          "[bounded][cvt]") {
    const Experiment ex = load_experiment(test::source_dir() / "configs/cvt_tipin.yaml");
    const IdentificationProblem problem(ex);
    auto ws = problem.make_workspace();
    std::vector<double> centre(problem.dimension());
    for (std::size_t j = 0; j < centre.size(); ++j)
        centre[j] = 0.5 * (problem.range_lower()[j] + problem.range_upper()[j]);
    const double full = problem.cost(centre.data(), *ws);
    REQUIRE(std::isfinite(full));
    CHECK(problem.cost(centre.data(), *ws, full * 1.0000001) == full);  // bound above: the full cost
    CHECK(problem.cost(centre.data(), *ws, std::numeric_limits<double>::infinity()) == full);
    for (double fraction : {0.9, 0.5, 0.01}) {
        const std::size_t before = ws->buffers.rhs_evaluations;
        const double partial = problem.cost(centre.data(), *ws, fraction * full);
        CHECK(partial >= fraction * full);
        CHECK(partial <= full);
        const std::size_t used = ws->buffers.rhs_evaluations - before;
        ws->buffers.rhs_evaluations = before;
        problem.cost(centre.data(), *ws);
        CHECK(used < ws->buffers.rhs_evaluations - before);  // it stopped early
    }
}

TEST_CASE("the swarm's path is bit-identical with and without bounded costs, on 1 and 2 threads",
          "[bounded][pso][threads][heavy]") {
    for (const char* config : {"cvt_tipin.yaml", "cvt_tipin_clean.yaml"}) {
        const Experiment ex = small_swarm_experiment(config);
        const IdentificationProblem problem(ex);
        ParallelEvaluator plain_inner(problem, EvaluatorOptions(1));
        RecordingEvaluator plain(plain_inner, false);
        const PsoSummary reference = run_pso(ex.estimation_settings.pso, box_of(problem), plain);
        for (int threads : {1, 2}) {
            INFO(config << " on " << threads << " thread(s)");
            ParallelEvaluator bounded_inner(problem, EvaluatorOptions(threads));
            RecordingEvaluator bounded(bounded_inner, true);
            const PsoSummary s = run_pso(ex.estimation_settings.pso, box_of(problem), bounded);
            CHECK(s.best == reference.best);
            CHECK(s.best_cost == reference.best_cost);
            CHECK(s.evaluations == reference.evaluations);
            CHECK(s.failed_evaluations == reference.failed_evaluations);
            REQUIRE(s.history.size() == reference.history.size());
            for (std::size_t k = 0; k < s.history.size(); ++k) {
                CHECK(s.history[k].best_cost == reference.history[k].best_cost);
                CHECK(s.history[k].evaluations == reference.history[k].evaluations);
            }
            CHECK(bounded.positions == plain.positions);            // every particle, every iteration
            CHECK(bounded.personal_bests == plain.personal_bests);  // every personal-best cost
            // The point of it: fewer right-hand sides for the same swarm.
            CHECK(bounded_inner.right_hand_sides() < plain_inner.right_hand_sides());
        }
    }
}

}  // namespace TVID_UNITY_ID

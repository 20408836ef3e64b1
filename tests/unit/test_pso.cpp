// Particle swarm (Yoshida & Takamatsu eq. 24) on functions with a known minimum.
#include <catch2/catch.hpp>
#include <cmath>

#include "tvid/optim/pso.hpp"

namespace TVID_UNITY_ID {  // unique to this file in a unity build (tests/CMakeLists.txt)

using namespace tvid;

namespace {

// Shifted quadratic bowl with its minimum 0 at (1, -2, 3), counting calls.
struct Bowl : CandidateEvaluator {
    long long calls = 0;
    void evaluate(const double* c, std::size_t count, std::size_t dim, double* costs) override {
        const double centre[3] = {1.0, -2.0, 3.0};
        for (std::size_t i = 0; i < count; ++i) {
            double s = 0;
            for (std::size_t j = 0; j < dim; ++j) s += (c[i * dim + j] - centre[j]) * (c[i * dim + j] - centre[j]);
            costs[i] = s;
            ++calls;
        }
    }
};

struct AlwaysFails : CandidateEvaluator {
    void evaluate(const double*, std::size_t count, std::size_t, double* costs) override {
        for (std::size_t i = 0; i < count; ++i) costs[i] = std::numeric_limits<double>::infinity();
    }
};

SearchBox box3() { return SearchBox{{-10, -10, -10}, {10, 10, 10}, {-5, -5, -5}, {5, 5, 5}}; }

}  // namespace

TEST_CASE("the grid start puts n^M particles on the range box", "[pso]") {
    PsoSettings s;
    s.grid = 3;
    std::size_t n = 0;
    const auto p = pso_initial_positions(s, box3(), n, 1);
    REQUIRE(n == 27);
    CHECK(p[0] == -5.0);
    CHECK(p[1] == -5.0);
    CHECK(p[3 * 1 + 0] == 0.0);   // particle 1: first coordinate moves first
    CHECK(p[3 * 26 + 2] == 5.0);  // last particle: the far corner
    s.grid = 2;
    pso_initial_positions(s, box3(), n, 1);
    CHECK(n == 8);
}

TEST_CASE("the Latin hypercube start puts one particle in each stratum of every parameter", "[pso]") {
    PsoSettings s;
    s.start = PsoStart::latin_hypercube;
    s.particles = 10;
    std::size_t n = 0;
    const auto p = pso_initial_positions(s, box3(), n, 7);
    REQUIRE(n == 10);
    for (std::size_t j = 0; j < 3; ++j) {
        std::vector<int> hits(10, 0);
        for (std::size_t i = 0; i < n; ++i) hits[static_cast<std::size_t>((p[i * 3 + j] + 5.0))]++;
        for (int h : hits) CHECK(h == 1);
    }
}

TEST_CASE("PSO finds the minimum of a bowl and reports its work", "[pso]") {
    PsoSettings s;  // paper defaults: grid 2, w = 1, c1 = c2 = 0.4
    s.iterations = 300;
    s.start = PsoStart::latin_hypercube;
    s.particles = 30;
    Bowl bowl;
    const PsoSummary r = run_pso(s, box3(), bowl);
    CHECK(r.best_cost < 1e-6);
    CHECK(r.best[0] == Approx(1.0).margin(1e-3));
    CHECK(r.best[1] == Approx(-2.0).margin(1e-3));
    CHECK(r.best[2] == Approx(3.0).margin(1e-3));
    CHECK(r.evaluations == bowl.calls);
    CHECK(r.history.size() == 301);
    CHECK(r.iterations == 300);
    CHECK(r.termination == "iteration limit");
    CHECK(r.termination_type == TerminationType::iteration_limit);
    // The best cost never increases.
    for (std::size_t k = 1; k < r.history.size(); ++k) CHECK(r.history[k].best_cost <= r.history[k - 1].best_cost);
    // Eq. 24 as printed: p(1) = p(0) + v(0) = p(0), so iteration 1 costs no simulation.
    CHECK(r.history[1].evaluations == r.history[0].evaluations);
    CHECK(r.history[0].evaluations == 30);
}

TEST_CASE("PSO is reproducible for a seed and differs across seeds and draw modes", "[pso]") {
    PsoSettings s;
    s.iterations = 20;
    s.start = PsoStart::uniform;
    s.particles = 12;
    Bowl a, b, c;
    const PsoSummary r1 = run_pso(s, box3(), a);
    const PsoSummary r2 = run_pso(s, box3(), b);
    CHECK(r1.best == r2.best);
    CHECK(r1.best_cost == r2.best_cost);
    s.seed = 2;
    const PsoSummary r3 = run_pso(s, box3(), c);
    CHECK(r3.best != r1.best);
    for (auto draw : {PsoRandomDraw::per_iteration, PsoRandomDraw::per_particle}) {
        s.seed = 1;
        s.draw = draw;
        Bowl d;
        CHECK(run_pso(s, box3(), d).best != r1.best);
    }
}

TEST_CASE("PSO particles stay inside the bounds", "[pso]") {
    struct Recorder : CandidateEvaluator {
        double lo = 1e300, hi = -1e300;
        void evaluate(const double* c, std::size_t count, std::size_t dim, double* costs) override {
            for (std::size_t i = 0; i < count; ++i) {
                for (std::size_t j = 0; j < dim; ++j) {
                    lo = std::min(lo, c[i * dim + j]);
                    hi = std::max(hi, c[i * dim + j]);
                }
                costs[i] = -c[i * dim];  // pulls toward the upper bound of the first parameter
            }
        }
    } rec;
    PsoSettings s;
    s.iterations = 50;
    const SearchBox box{{0, 0}, {1, 1}, {0.2, 0.2}, {0.8, 0.8}};
    const PsoSummary r = run_pso(s, box, rec);
    CHECK(rec.lo >= 0.0);
    CHECK(rec.hi <= 1.0);
    CHECK(r.best[0] == 1.0);
}

TEST_CASE("PSO reports when every candidate fails", "[pso]") {
    PsoSettings s;
    s.iterations = 3;
    AlwaysFails f;
    const PsoSummary r = run_pso(s, box3(), f);
    CHECK(r.termination == "all candidates failed");
    CHECK(r.termination_type == TerminationType::all_failed);
    CHECK(r.failed_evaluations == r.evaluations);
    CHECK(std::isinf(r.best_cost));
}

TEST_CASE("a progress callback can stop the swarm", "[pso]") {
    PsoSettings s;
    s.iterations = 100;
    Bowl bowl;
    const PsoSummary r = run_pso(s, box3(), bowl, [](const HistoryRow& row) { return row.iteration < 4; });
    CHECK(r.termination == "stopped");
    CHECK(r.termination_type == TerminationType::stopped);
    CHECK(r.iterations == 4);
}

TEST_CASE("the swarm says how settled it is at its end: spread of the personal bests and recent improvement", "[pso]") {
    PsoSettings s;
    s.start = PsoStart::latin_hypercube;
    s.particles = 30;
    Bowl bowl;
    s.iterations = 300;  // long enough to gather every particle at the minimum
    const PsoSummary settled = run_pso(s, box3(), bowl);
    REQUIRE(settled.convergence.spread.size() == 3);
    CHECK(settled.convergence.window == 30);  // a tenth of the iterations
    CHECK(settled.convergence.max_spread < 0.01);
    CHECK(settled.convergence.recent_improvement >= 0.0);
    // The improvement is the global best's relative fall over the window, from the history.
    const double now = settled.history.back().best_cost, before = settled.history[300 - 30].best_cost;
    CHECK(settled.convergence.recent_improvement == Approx((before - now) / now));
    s.iterations = 12;  // stopped early: the personal bests still span much of the box
    Bowl again;
    const PsoSummary early = run_pso(s, box3(), again);
    CHECK(early.convergence.window == 10);
    CHECK(early.convergence.max_spread > 0.05);  // the verdict's still-spread threshold
    CHECK(early.convergence.recent_improvement > 0.01);
    double widest = 0;
    for (double v : early.convergence.spread) widest = std::max(widest, v);
    CHECK(widest == early.convergence.max_spread);
}

}  // namespace TVID_UNITY_ID

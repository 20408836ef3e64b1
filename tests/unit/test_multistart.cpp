// Multistart LM on a problem with many local minima: a Latin-hypercube sample of starts,
// the best kept, every start reported, the same result for any thread count.
#include <catch2/catch.hpp>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <future>
#include <limits>
#include <memory>
#include <set>

#include "support/sinusoid_fit.hpp"
#include "tvid/optim/multistart.hpp"
#include "tvid/optim/multistart_race.hpp"

namespace TVID_UNITY_ID {  // unique to this file in a unity build (tests/CMakeLists.txt)

using namespace tvid;
using tvid::test::SinusoidFit;

namespace {

// ω's range [1, 5] in 20 slices of 0.2: the start in the slice of the truth lies in its
// basin (half-width about π/10 s ≈ 0.3 rad/s); most others do not.
const SearchBox kBox{{0.0, 0.1}, {10.0, 10.0}, {0.5, 1.0}, {3.0, 5.0}};

LeastSquaresFactory sinusoid_factory() {
    return [](const ThreadBudget&) { return std::make_unique<SinusoidFit>(); };
}

MultistartSettings starts(int n, std::uint64_t seed = 5) {
    MultistartSettings s;
    s.starts = n;
    s.seed = seed;
    return s;
}

}  // namespace

TEST_CASE("multistart points are a seeded Latin hypercube of the range box", "[multistart]") {
    const auto p = multistart_points(starts(10), kBox);
    REQUIRE(p.size() == 20);
    for (std::size_t j = 0; j < 2; ++j) {
        std::set<int> strata;  // one point in each of the 10 slices of every parameter's range
        for (std::size_t i = 0; i < 10; ++i) {
            const double u = (p[i * 2 + j] - kBox.range_lower[j]) / (kBox.range_upper[j] - kBox.range_lower[j]);
            CHECK(u >= 0.0);
            CHECK(u < 1.0);
            strata.insert(static_cast<int>(u * 10));
        }
        CHECK(strata.size() == 10);
    }
    CHECK(multistart_points(starts(10), kBox) == p);
    CHECK(multistart_points(starts(10, 6), kBox) != p);
}

TEST_CASE("multistart finds the global minimum where single starts stop in local ones", "[multistart]") {
    const MultistartSummary s = run_multistart(starts(20), LmSettings{}, kBox, 2, sinusoid_factory());
    REQUIRE(s.starts.size() == 20);
    REQUIRE(s.best_start >= 1);
    CHECK(s.best[0] == Approx(SinusoidFit::kAmplitude).epsilon(1e-9));
    CHECK(s.best[1] == Approx(SinusoidFit::kFrequency).epsilon(1e-9));
    CHECK(s.best_cost < 1e-18);
    CHECK(s.success);
    CHECK(s.termination.rfind("best of 20 starts: ", 0) == 0);
    int stuck = 0;
    long long evaluations = 0;
    int iterations = 0;
    const auto points = multistart_points(starts(20), kBox);
    for (const StartResult& r : s.starts) {
        CHECK(r.initial == std::vector<double>(points.begin() + (r.start - 1) * 2, points.begin() + r.start * 2));
        CHECK(r.best_cost >= s.best_cost);
        CHECK(r.best_cost <= r.initial_cost);
        CHECK(r.termination != "not run");
        stuck += r.best_cost > 1.0 ? 1 : 0;
        evaluations += r.evaluations;
        iterations += r.iterations;
    }
    CHECK(stuck > 0);  // some starts end in a local minimum: the problem needs the spread
    CHECK(s.best_cost == s.starts[static_cast<std::size_t>(s.best_start - 1)].best_cost);
    CHECK(s.evaluations == evaluations);
    CHECK(s.iterations == iterations);
    // History: the starts one after the other, numbered on, best so far.
    std::size_t rows = 0;
    for (const StartResult& r : s.starts) rows += r.history.size();
    REQUIRE(s.history.size() == rows);
    for (std::size_t k = 1; k < s.history.size(); ++k) {
        CHECK(s.history[k].iteration == static_cast<int>(k));
        CHECK(s.history[k].evaluations >= s.history[k - 1].evaluations);
        CHECK(s.history[k].best_cost <= s.history[k - 1].best_cost);
    }
    CHECK(s.history.back().evaluations == s.evaluations);
    CHECK(s.history.back().best_cost == s.best_cost);
}

TEST_CASE("multistart gives the same result for any thread count", "[multistart]") {
    const MultistartSummary one = run_multistart(starts(7), LmSettings{}, kBox, 1, sinusoid_factory());
    const MultistartSummary three = run_multistart(starts(7), LmSettings{}, kBox, 3, sinusoid_factory());
    CHECK(one.threads == 1);
    CHECK(three.threads == 3);
    CHECK(one.best == three.best);
    CHECK(one.best_start == three.best_start);
    CHECK(one.best_cost == three.best_cost);
    REQUIRE(one.history.size() == three.history.size());
    for (std::size_t k = 0; k < one.history.size(); ++k) {
        CHECK(one.history[k].best_cost == three.history[k].best_cost);
        CHECK(one.history[k].evaluations == three.history[k].evaluations);
    }
    for (std::size_t i = 0; i < one.starts.size(); ++i) {
        CHECK(one.starts[i].best == three.starts[i].best);
        CHECK(one.starts[i].iterations == three.starts[i].iterations);
    }
}

TEST_CASE("multistart: per-start iteration cap, stop, and bad settings", "[multistart]") {
    MultistartSettings capped = starts(4);
    capped.max_iterations = 2;
    const MultistartSummary s = run_multistart(capped, LmSettings{}, kBox, 2, sinusoid_factory());
    for (const StartResult& r : s.starts) CHECK(r.iterations <= 2);

    int calls = 0;
    const MultistartSummary stopped = run_multistart(starts(6), LmSettings{}, kBox, 1, sinusoid_factory(),
                                                     [&](const HistoryRow&) { return ++calls < 3; });
    CHECK(stopped.termination == "stopped");
    CHECK(stopped.termination_type == TerminationType::stopped);
    CHECK_FALSE(stopped.success);
    CHECK(std::count_if(stopped.starts.begin(), stopped.starts.end(),
                        [](const StartResult& r) { return r.termination == "not run"; }) >= 4);
    CHECK_THROWS_AS(run_multistart(starts(0), LmSettings{}, kBox, 1, sinusoid_factory()), std::invalid_argument);
}

namespace {
// The sinusoid, whose model cannot be evaluated at frequencies above 4 (as a simulation
// that diverges for a stiff candidate), and says so.
struct SinusoidFailingAbove4 : SinusoidFit {
    bool residuals(const double* x, double* r) override { return x[1] <= 4.0 && SinusoidFit::residuals(x, r); }
    bool jacobian(const double* x, double* r, Eigen::MatrixXd& J) override {
        return x[1] <= 4.0 && SinusoidFit::jacobian(x, r, J);
    }
    std::string failure(const double* x) override { return x[1] > 4.0 ? "frequency above 4" : ""; }
};
}  // namespace

TEST_CASE("multistart says how many starts failed and why the first of them did", "[multistart]") {
    const LeastSquaresFactory factory = [](const ThreadBudget&) { return std::make_unique<SinusoidFailingAbove4>(); };
    MultistartSettings once = starts(20);
    once.max_draws = 1;  // no redraw: a start at a point that cannot be simulated fails
    const MultistartSummary s = run_multistart(once, LmSettings{}, kBox, 2, factory);
    int failed = 0, first = 0;
    for (const StartResult& r : s.starts)
        if (r.initial[1] > 4.0) {
            ++failed;
            if (first == 0) first = r.start;
            CHECK(r.termination == "start failed: frequency above 4");  // each start's own LM says why
            CHECK(r.draws == 1);
        }
    REQUIRE(failed > 0);
    REQUIRE(failed < 20);
    CHECK(s.termination.find("(" + std::to_string(failed) + " of 20 starts failed, each after 1 drawn point; start " +
                             std::to_string(first) + ": start failed: frequency above 4)") != std::string::npos);

    // Every start failing at every point drawn: the summary still says why, and how many were drawn.
    const SearchBox high{{0.0, 4.5}, {10.0, 10.0}, {0.5, 4.5}, {3.0, 5.0}};
    const MultistartSummary all = run_multistart(starts(4), LmSettings{}, high, 1, factory);
    CHECK(all.termination ==
          "every start failed (4 of 4 starts failed, each after 10 drawn points; start 1: start failed: frequency above 4)");
    for (const StartResult& r : all.starts) CHECK(r.draws == 10);
}

TEST_CASE("multistart redraws a start whose point cannot be simulated, so every start asked for runs", "[multistart]") {
    const LeastSquaresFactory factory = [](const ThreadBudget&) { return std::make_unique<SinusoidFailingAbove4>(); };
    const MultistartSummary s = run_multistart(starts(20), LmSettings{}, kBox, 2, factory);
    int redrawn = 0;
    for (const StartResult& r : s.starts) {
        INFO("start " << r.start);
        CHECK(std::isfinite(r.best_cost));   // every start ran
        CHECK(r.termination_type != TerminationType::start_failed);
        CHECK(r.initial[1] <= 4.0);          // from a point that can be simulated
        CHECK(r.initial[1] >= kBox.range_lower[1]);
        CHECK(r.initial[1] <= kBox.range_upper[1]);
        CHECK(r.draws >= 1);
        CHECK(r.draws <= 10);
        redrawn += r.draws > 1;
    }
    CHECK(redrawn > 0);  // the Latin hypercube put some starts above 4
    // The redraws come from each start's own stream: the same on one thread.
    const MultistartSummary one = run_multistart(starts(20), LmSettings{}, kBox, 1, factory);
    for (std::size_t i = 0; i < s.starts.size(); ++i) {
        CHECK(one.starts[i].draws == s.starts[i].draws);
        CHECK(one.starts[i].initial == s.starts[i].initial);
    }
    CHECK(one.best == s.best);
    // A redraw is a point of the range box from (seed, start, draw) alone.
    const auto a = multistart_redraw(starts(20), kBox, 3, 2), b = multistart_redraw(starts(20), kBox, 3, 2);
    CHECK(a == b);
    CHECK(multistart_redraw(starts(20), kBox, 3, 3) != a);
    CHECK(multistart_redraw(starts(20, 6), kBox, 3, 2) != a);
}

TEST_CASE("multistart races its starts: the worse half stop at each rung, the best start's path is unchanged",
          "[multistart]") {
    MultistartSettings raced = starts(20), full = starts(20);
    full.race = false;
    const MultistartSummary r = run_multistart(raced, LmSettings{}, kBox, 2, sinusoid_factory());
    const MultistartSummary f = run_multistart(full, LmSettings{}, kBox, 2, sinusoid_factory());
    REQUIRE(r.best_start >= 1);
    CHECK(r.best_start == f.best_start);
    CHECK(r.best == f.best);  // paused at the rungs, never restarted: the same path
    CHECK(r.best_cost == f.best_cost);
    CHECK(r.success);
    int raced_out = 0;
    for (std::size_t i = 0; i < r.starts.size(); ++i) {
        const StartResult& s = r.starts[i];
        INFO("start " << s.start << ": " << s.termination);
        CHECK(f.starts[i].termination_type != TerminationType::raced_out);
        if (s.termination_type != TerminationType::raced_out) {
            CHECK(s.best == f.starts[i].best);  // a start that was not stopped ran as without the race
            continue;
        }
        ++raced_out;
        CHECK(s.termination.rfind("raced out after " + std::to_string(s.iterations) + " iterations: cost ", 0) == 0);
        CHECK(s.termination.find(" starts still running)") != std::string::npos);
        CHECK_FALSE(s.success);
        // Stopped at a rung (4, 8, 16, ... steps), where the full run had the same cost.
        CHECK((s.iterations == 4 || s.iterations == 8 || s.iterations == 16 || s.iterations == 32));
        REQUIRE(f.starts[i].history.size() > static_cast<std::size_t>(s.iterations));
        CHECK(s.best_cost == f.starts[i].history[static_cast<std::size_t>(s.iterations)].best_cost);
        CHECK(s.best_cost > r.best_cost);
        // Not falling fast: above half its cost at the previous rung (its start for the first).
        const std::size_t previous = s.iterations == 4 ? 0 : static_cast<std::size_t>(s.iterations / 2);
        CHECK(s.best_cost >= 0.5 * f.starts[i].history[previous].best_cost);
        CHECK(s.termination.find(" since iteration " + std::to_string(previous) + "), the best ") != std::string::npos);
    }
    CHECK(raced_out >= 3);
    CHECK(r.evaluations < f.evaluations);
}

TEST_CASE("multistart's race gives the same result for any thread count, also in groups of 32", "[multistart]") {
    for (int n : {7, 40}) {
        INFO(n << " starts");
        const MultistartSummary one = run_multistart(starts(n), LmSettings{}, kBox, 1, sinusoid_factory());
        const MultistartSummary three = run_multistart(starts(n), LmSettings{}, kBox, 3, sinusoid_factory());
        CHECK(one.best == three.best);
        CHECK(one.best_start == three.best_start);
        REQUIRE(one.starts.size() == three.starts.size());
        for (std::size_t i = 0; i < one.starts.size(); ++i) {
            CHECK(one.starts[i].termination == three.starts[i].termination);
            CHECK(one.starts[i].iterations == three.starts[i].iterations);
            CHECK(one.starts[i].best == three.starts[i].best);
        }
        CHECK(one.best_cost < 1e-18);
    }
    MultistartSettings bad = starts(4);
    bad.race_iterations = 0;
    CHECK(validate(bad).has_value());
}

TEST_CASE("the starts of a race split the cores: the last one running has them all", "[multistart]") {
    // Three starts on two cores: each start holding a core counts in the budget, so a
    // parallel region of a start takes 2 threads alone and 1 beside another.
    ThreadBudget share(2);
    StartRace race(3, 2, 4, 100, std::numeric_limits<double>::infinity(), &share);
    REQUIRE(race.enter(0));
    CHECK(share.team() == 2);
    REQUIRE(race.enter(1));
    CHECK(share.team() == 1);
    race.leave(0, 5.0);  // converged: its core goes to the others
    CHECK(share.team() == 2);
    REQUIRE(race.enter(2));
    CHECK(share.team() == 1);
    race.leave(1, 6.0);
    race.leave(2, 7.0);
    CHECK(share.team() == 2);  // no start running: a region would take every core
}

TEST_CASE("a start whose fate at a rung is settled goes on at once, the others wait for the rung", "[multistart]") {
    using namespace std::chrono_literals;
    const double inf = std::numeric_limits<double>::infinity();
    StartRace race(3, 3, 4, 100, inf);
    std::future<bool> waiting, falling;
    struct StopOnExit {  // should a check fail, no thread is left waiting at the rung
        StartRace& race;
        ~StopOnExit() { race.stop(); }
    } stop_on_exit{race};
    for (std::size_t i = 0; i < 3; ++i) {
        REQUIRE(race.enter(i));
        REQUIRE(race.step(i, 0, 100.0));
    }
    // Start 2 at the first rung, not falling (90 of 100): its rank depends on the two on
    // their way, so it waits.
    waiting = std::async(std::launch::async, [&] { return race.step(2, 4, 90.0); });
    CHECK(waiting.wait_for(50ms) == std::future_status::timeout);
    // Start 0 fell below half of its start's cost: the rung keeps it whatever the others
    // bring, so it goes on without waiting, although start 1 has not arrived.
    falling = std::async(std::launch::async, [&] { return race.step(0, 4, 10.0); });
    REQUIRE(falling.wait_for(10s) == std::future_status::ready);
    CHECK(falling.get());
    CHECK(waiting.wait_for(50ms) == std::future_status::timeout);
    // Start 1 arrives last: the rung is decided. Three reached it, two are kept: start 0
    // (gone on) and the better of 1 and 2; start 2 stops.
    CHECK(race.step(1, 4, 80.0));
    REQUIRE(waiting.wait_for(10s) == std::future_status::ready);
    CHECK_FALSE(waiting.get());
    CHECK(race.verdict(0).empty());
    CHECK(race.verdict(1).empty());
    CHECK(race.verdict(2) ==
          "raced out after 4 iterations: cost 90 (down 10 % since iteration 0), the best 10 (rank 3 of the 3 starts "
          "still running)");
    race.leave(2, 90.0);
    race.leave(0, 5.0);
    race.leave(1, 7.0);
}

}  // namespace TVID_UNITY_ID

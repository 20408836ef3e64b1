// Candidates scored in SIMD groups (lib/tvid/estimation/batch_cost.hpp) cost exactly what
// IdentificationProblem::cost gives each alone, bit for bit: with and without a bound,
// for candidates that fail, that are not finite, in full and in partial groups, on the
// CVT preset, the engine block (cylinders, warm-up shooting, substeps) and a custom
// network with every other element kind, also when a whole batch is scored at once on two
// threads with the groups formed anew from the survivors. The swarm then takes the same
// path with and without the groups.
#include <catch2/catch.hpp>

#include <algorithm>
#include <atomic>
#include <bit>
#include <cmath>
#include <cstdint>
#include <fstream>
#include <limits>
#include <memory>
#include <nlohmann/json.hpp>
#include <random>
#include <sstream>
#include <vector>

#include "support/test_files.hpp"
#include "tvid/estimation/batch_cost.hpp"
#include "tvid/estimation/identification_problem.hpp"
#include "tvid/estimation/parallel_evaluator.hpp"
#include "tvid/experiment/experiment.hpp"
#include "tvid/optim/pso.hpp"

namespace TVID_UNITY_ID {  // unique to this file in a unity build (tests/CMakeLists.txt)

using namespace tvid;

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

bool same_bits(double a, double b) { return std::bit_cast<std::uint64_t>(a) == std::bit_cast<std::uint64_t>(b); }

// Random points of the search box of `problem`, as a flat list.
std::vector<double> points_in_box(const IdentificationProblem& problem, std::size_t count, std::uint64_t seed) {
    std::mt19937_64 rng(seed);
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    const std::size_t m = problem.dimension();
    std::vector<double> points(count * m);
    for (std::size_t i = 0; i < count; ++i)
        for (std::size_t j = 0; j < m; ++j) {
            const double a = problem.range_lower()[j], b = problem.range_upper()[j];
            points[i * m + j] = a + (b - a) * unit(rng);
        }
    return points;
}

// Counts the candidates whose `costs` differ in any bit from their costs scored alone.
std::size_t differ_from_alone(const IdentificationProblem& problem, const std::vector<double>& points,
                              const std::vector<double>& bounds, const std::vector<double>& costs) {
    const std::size_t m = problem.dimension();
    auto scalar = problem.make_workspace();
    std::size_t differ = 0;
    for (std::size_t i = 0; i < costs.size(); ++i) {
        const double alone = problem.cost(points.data() + i * m, *scalar, bounds[i]);
        if (!same_bits(alone, costs[i])) {
            ++differ;
            UNSCOPED_INFO("candidate " << i << ": alone " << alone << ", batched " << costs[i] << ", bound " << bounds[i]);
        }
    }
    return differ;
}

// Scores `points` one at a time and in groups of up to `group` with the given bounds, and
// counts the candidates whose costs differ in any bit.
std::size_t mismatches(const IdentificationProblem& problem, const std::vector<double>& points,
                       const std::vector<double>& bounds, std::size_t group) {
    const std::size_t m = problem.dimension(), count = points.size() / m;
    BatchWorkspace batch(problem);
    std::vector<double> costs(count);
    for (std::size_t first = 0; first < count; first += group) {
        const std::size_t size = std::min(group, count - first);
        batch_costs(problem, points.data() + first * m, size, bounds.data() + first, batch, costs.data() + first);
    }
    return differ_from_alone(problem, points, bounds, costs);
}

// Scores all of `points` in one call on `threads` threads, with the groups formed anew
// as the windows go on, and counts the candidates whose costs differ in any bit from
// their costs alone.
std::size_t mismatches_at_once(const IdentificationProblem& problem, const std::vector<double>& points,
                               const std::vector<double>& bounds, int threads) {
    const std::size_t m = problem.dimension(), count = points.size() / m;
    std::vector<std::unique_ptr<BatchWorkspace>> owned;
    std::vector<BatchWorkspace*> workspaces;
    for (int t = 0; t < threads; ++t) {
        owned.push_back(std::make_unique<BatchWorkspace>(problem));
        workspaces.push_back(owned.back().get());
    }
    std::vector<double> costs(count);
    REQUIRE(batch_costs(problem, points.data(), count, bounds.data(), workspaces, nullptr, costs.data()));
    return differ_from_alone(problem, points, bounds, costs);
}

// Bounds that cut the candidates early, late, exactly at the end, or not at all.
std::vector<double> mixed_bounds(const IdentificationProblem& problem, const std::vector<double>& points) {
    const std::size_t m = problem.dimension(), count = points.size() / m;
    auto ws = problem.make_workspace();
    const double factors[] = {kInf, 0.3, 1.0 - 1e-12, 1.0, 1.001, 0.95};
    std::vector<double> bounds(count);
    for (std::size_t i = 0; i < count; ++i) {
        const double full = problem.cost(points.data() + i * m, *ws);
        const double f = factors[i % 6];
        bounds[i] = std::isfinite(full) && std::isfinite(f) ? f * full : kInf;
    }
    return bounds;
}

// A recording for the custom network: a smooth drive torque and some outputs.
std::string custom_recording() {
    std::ostringstream s;
    s << "t,u,w,a,T\n";
    for (int i = 0; i <= 300; ++i) {
        const double t = 1e-3 * i;
        s << t << ',' << 20.0 * std::sin(40.0 * t) + 5.0 << ',' << 3.0 * std::sin(25.0 * t) << ',' << 0.1 * t << ','
          << 2.0 * std::cos(30.0 * t) << '\n';
    }
    return s.str();
}

// Every element kind but the cylinder: a gear mesh with a smoothed clearance, a stop
// with the non-smooth law (no sigma), springs, friction and a scaled input torque; three
// outputs (speed, angle, torque), two windows, the l2 cost, RK4 in four substeps.
std::string custom_network(const std::string& initial_state) {
    return "tvid: 1\n"
           "data: { file: rec.csv, time: t }\n"
           "model:\n"
           "  nodes:\n"
           "    - { name: motor, J: J_m }\n"
           "    - { name: load, inverse_J: 20 }\n"
           "  elements:\n"
           "    - { type: torque, name: drive, node: motor, input: T_in, offset: d_in, scale: 2 }\n"
           "    - { type: spring_damper, name: shaft, between: [motor, load], k: k_s, c: 0.5 }\n"
           "    - { type: clearance, name: stop, between: [load], k_minus: 100, k_plus: 200, c_minus: 1, c_plus: 2, mu: 0.002 }\n"
           "    - { type: friction, name: bearing, node: load, c: c_f }\n"
           "    - { type: gear_mesh, name: stage, between: [motor, load], ratio: 3, k: 5000, c: 1, mu: 0.01, sigma: 2000 }\n"
           "    - { type: spring_damper, name: mount, between: [motor, ground], k: 50 }\n"
           "inputs: { T_in: u }\n"
           "outputs:\n"
           "  w_load:  { column: w, speed: load }\n"
           "  a_motor: { column: a, angle: motor }\n"
           "  T_shaft: { column: T, torque: shaft, offset: d_T }\n"
           "parameters:\n"
           "  J_m:  { init: 0.1, min: 0.01, max: 1 }\n"
           "  d_in: { value: 0.5 }\n"
           "  k_s:  { init: 1000, min: 10, max: 1.0e5 }\n"
           "  c_f:  { init: 0.1, min: 0, max: 10 }\n"
           "  d_T:  { init: 0, min: -10, max: 10 }\n"
           "windows:\n"
           "  estimation: [ { samples: [10, 120] }, { samples: [150, 290] } ]\n"
           "initial_state: " + initial_state + "\n"
           "simulation: { method: rk4, step: 2.5e-4 }\n"
           "estimation: { cost: l2 }\n";
}

}  // namespace

TEST_CASE("CVT candidates cost the same bits in SIMD groups as alone, with and without bounds", "[batch][cvt]") {
    const Experiment ex = load_experiment(test::source_dir() / "configs/cvt_tipin.yaml");
    const IdentificationProblem problem(ex);
    REQUIRE(batch_supported(problem));
    const std::size_t m = problem.dimension();
    std::vector<double> points = points_in_box(problem, 45, 3);
    // Wild candidates: a very steep clearance (σμ far beyond the paper's), one at the
    // lower bounds (a soft, fast-diverging drivetrain), and two that are not finite.
    points[0 * m + 6] = 1.0e5;
    points[0 * m + 5] = 0.05;
    for (std::size_t j = 0; j < m; ++j) points[1 * m + j] = problem.lower()[j];
    points[2 * m + 3] = std::numeric_limits<double>::quiet_NaN();
    points[7 * m + 0] = kInf;
    const std::vector<double> unbounded(points.size() / m, kInf);
    CHECK(mismatches(problem, points, unbounded, kBatchLanes) == 0);
    const std::vector<double> bounds = mixed_bounds(problem, points);
    CHECK(mismatches(problem, points, bounds, kBatchLanes) == 0);
    CHECK(mismatches(problem, points, bounds, 5) == 0);  // partial groups
    CHECK(mismatches(problem, points, bounds, 1) == 0);
    CHECK(mismatches_at_once(problem, points, unbounded, 1) == 0);
    CHECK(mismatches_at_once(problem, points, bounds, 1) == 0);
    CHECK(mismatches_at_once(problem, points, bounds, 2) == 0);
}

TEST_CASE("the groups are formed anew from the candidates still live as the window goes on", "[batch][cvt]") {
    const Experiment ex = load_experiment(test::source_dir() / "configs/cvt_tipin.yaml");
    const IdentificationProblem problem(ex);
    const std::size_t m = problem.dimension();
    const Window& w = ex.estimation.at(0);
    // One window simulation of one pack: a right-hand side at its start, then 4 a sample.
    const std::size_t window_packs = 1 + 4 * (w.last - w.start);
    const std::size_t count = 2 * kBatchLanes;
    const std::vector<double> points = points_in_box(problem, count, 21);

    // Every candidate but the first of each group of 16 is cut at its first sample (a
    // bound of 0): fixed groups would both run to the end for their one survivor.
    std::vector<double> bounds(count, 0.0);
    bounds[0] = bounds[kBatchLanes] = kInf;
    BatchWorkspace ws(problem);
    std::vector<double> costs(count);
    batch_costs(problem, points.data(), count, bounds.data(), ws, costs.data());
    const double pieces = static_cast<double>(kRegroupPieces);
    // Both groups run the first of the pieces, then the two survivors share one group.
    CHECK(static_cast<double>(ws.pack_rhs_evaluations) <= (1.0 + 1.5 / pieces) * static_cast<double>(window_packs));
    CHECK(static_cast<double>(ws.pack_rhs_evaluations) >= static_cast<double>(window_packs));
    auto scalar = problem.make_workspace();
    for (std::size_t i = 0; i < count; ++i) CHECK(same_bits(costs[i], problem.cost(points.data() + i * m, *scalar, bounds[i])));
    CHECK(costs[1] < costs[0]);  // a cut candidate stops at its partial sum

    // Unbounded, the two groups run the whole window.
    BatchWorkspace full(problem);
    batch_costs(problem, points.data(), count, nullptr, full, costs.data());
    CHECK(full.pack_rhs_evaluations >= 2 * window_packs);
}

TEST_CASE("a stop request ends a regrouped batch and says so", "[batch][cvt]") {
    const Experiment ex = load_experiment(test::source_dir() / "configs/cvt_tipin.yaml");
    const IdentificationProblem problem(ex);
    const std::vector<double> points = points_in_box(problem, 40, 4);
    BatchWorkspace ws(problem);
    BatchWorkspace* const one[] = {&ws};
    std::vector<double> costs(40, 0.0);
    const std::atomic<bool> stop{true};
    CHECK_FALSE(batch_costs(problem, points.data(), 40, nullptr, one, &stop, costs.data()));
    for (double c : costs) CHECK(c == kInf);
    CHECK(ws.pack_rhs_evaluations == 0);
}

TEST_CASE("a group counts the right-hand sides its candidates' own simulations need", "[batch][cvt]") {
    const Experiment ex = load_experiment(test::source_dir() / "configs/cvt_tipin.yaml");
    const IdentificationProblem problem(ex);
    const std::vector<double> points = points_in_box(problem, 11, 5);
    const std::vector<double> bounds = mixed_bounds(problem, points);
    auto scalar = problem.make_workspace();
    BatchWorkspace batch(problem);
    std::vector<double> costs(11);
    batch_costs(problem, points.data(), 11, bounds.data(), batch, costs.data());
    for (std::size_t i = 0; i < 11; ++i) problem.cost(points.data() + i * problem.dimension(), *scalar, bounds[i]);
    CHECK(batch.rhs_evaluations + batch.scalar->buffers.rhs_evaluations == scalar->buffers.rhs_evaluations);
}

TEST_CASE("engine candidates (cylinders, warm-up shooting, substeps) cost the same bits in a group", "[batch][engine]") {
    const Experiment ex = load_experiment(test::source_dir() / "configs/engine_idle_clean.yaml");
    const IdentificationProblem problem(ex);
    REQUIRE(batch_supported(problem));
    const auto truth = nlohmann::json::parse(test::read_text(test::source_dir() / "data/engine/truth.json"));
    std::vector<double> points;
    for (double scale : {1.0, 1.08, 0.93})
        for (const std::string& name : problem.free_names())
            points.push_back(truth["parameters"][name].get<double>() * (name == "J2" ? 1.0 : scale));
    auto ws = problem.make_workspace();
    const double second = problem.cost(points.data() + problem.dimension(), *ws);
    REQUIRE(std::isfinite(second));
    const std::vector<double> bounds = {kInf, 0.5 * second, kInf};
    CHECK(mismatches(problem, points, bounds, kBatchLanes) == 0);
    CHECK(mismatches_at_once(problem, points, bounds, 2) == 0);
}

TEST_CASE("a drive under a sampled controller costs the same bits in a group, each window marched whole",
          "[batch][sampled_controller][heavy]") {
    const Experiment ex = load_experiment(test::source_dir() / "configs/digital_drive.yaml");
    const IdentificationProblem problem(ex);
    REQUIRE(batch_supported(problem));
    const std::vector<double> points = points_in_box(problem, 2 * kBatchLanes + 3, 11);
    auto ws = problem.make_workspace();
    const double third = problem.cost(points.data() + 2 * problem.dimension(), *ws);
    REQUIRE(std::isfinite(third));
    std::vector<double> bounds(2 * kBatchLanes + 3, kInf);
    bounds[2] = 0.5 * third;  // cut short in a lane
    CHECK(mismatches(problem, points, bounds, kBatchLanes) == 0);
    CHECK(mismatches_at_once(problem, points, bounds, 2) == 0);
}

TEST_CASE("a custom network with every element kind but the cylinder costs the same bits in a group",
          "[batch][network]") {
    test::TempDir dir;
    dir.write("rec.csv", custom_recording());
    for (const std::string start : {"rest", "equilibrium"}) {
        INFO("initial_state: " << start);
        const Experiment ex = load_experiment(dir.write("custom.yaml", custom_network(start)));
        const IdentificationProblem problem(ex);
        REQUIRE(batch_supported(problem));
        std::vector<double> points = points_in_box(problem, 21, 9);
        points[4 * problem.dimension()] = 1e-7;  // a motor inertia that makes RK4 diverge
        CHECK(mismatches(problem, points, std::vector<double>(21, kInf), kBatchLanes) == 0);
        CHECK(mismatches(problem, points, mixed_bounds(problem, points), kBatchLanes) == 0);
        CHECK(mismatches_at_once(problem, points, mixed_bounds(problem, points), 2) == 0);
    }
}

TEST_CASE("the swarm takes the same path with and without SIMD groups, on 1 and 2 threads", "[batch][pso][heavy]") {
    const Experiment ex = load_experiment(test::source_dir() / "configs/cvt_tipin.yaml",
                                          {{"estimation.pso.start", "latin_hypercube"},
                                           {"estimation.pso.particles", "40"},
                                           {"estimation.pso.iterations", "12"}});
    const IdentificationProblem problem(ex);
    const SearchBox box{problem.lower(), problem.upper(), problem.range_lower(), problem.range_upper()};
    auto run = [&](int threads, bool groups) {
        ParallelEvaluator evaluator(problem, EvaluatorOptions(threads));
        evaluator.set_batching(groups);
        REQUIRE(evaluator.batching() == groups);
        return run_pso(ex.estimation_settings.pso, box, evaluator);
    };
    const PsoSummary reference = run(1, false);
    for (const auto& [threads, groups] : {std::pair{1, true}, std::pair{2, true}, std::pair{2, false}}) {
        INFO(threads << " threads, groups " << groups);
        const PsoSummary s = run(threads, groups);
        CHECK(same_bits(s.best_cost, reference.best_cost));
        CHECK(s.best == reference.best);
        REQUIRE(s.history.size() == reference.history.size());
        for (std::size_t k = 0; k < s.history.size(); ++k) CHECK(same_bits(s.history[k].best_cost, reference.history[k].best_cost));
    }
}

TEST_CASE("the measured bench's candidates cost the same bits in a group, a stiff one as alone, a too-fast one failing in both",
          "[batch][bench]") {
    // A speed source, a steady start, two normalised outputs and gears. A stiff stage-2
    // mesh passes RK4's stability limit at the bench's step: its window takes substeps
    // (stable_step.hpp), scored alone out of its group, to the same bits. One far stiffer
    // than the substeps reach has no steady start that Newton's differenced Jacobian finds
    // (its residual never falls): refused there, in a group as alone, where it once passed
    // as converged and diverged in the simulation.
    const Experiment ex = load_experiment(test::source_dir() / "configs/aalto_bench.yaml",
                                          {parse_override("windows.estimation=[ { samples: [0, 1500] } ]")});
    const IdentificationProblem problem(ex);
    REQUIRE(batch_supported(problem));
    const std::size_t m = problem.dimension();
    std::vector<double> points;
    for (double scale : {1.0, 1.1, 0.9, 1.05, 0.97})
        for (std::size_t j = 0; j < m; ++j) points.push_back(problem.initial()[j] * scale);
    const auto k_2 = static_cast<std::size_t>(
        std::find(problem.free_names().begin(), problem.free_names().end(), "k_2") - problem.free_names().begin());
    REQUIRE(k_2 < m);
    points[3 * m + k_2] = 1.0e5;
    points[4 * m + k_2] = 1.0e9;
    auto ws = problem.make_workspace();
    const long long subdivided = problem.subdivided_starts();
    CHECK(std::isfinite(problem.cost(points.data() + 3 * m, *ws)));
    CHECK(problem.subdivided_starts() == subdivided + 1);
    CHECK_FALSE(std::isfinite(problem.cost(points.data() + 4 * m, *ws)));
    INFO(problem.failure(points.data() + 4 * m, *ws));
    CHECK(problem.failure(points.data() + 4 * m, *ws).find("Newton's method did not converge to a steady motion") !=
          std::string::npos);
    CHECK(std::isfinite(problem.cost(points.data(), *ws)));
    CHECK(mismatches(problem, points, std::vector<double>(5, kInf), kBatchLanes) == 0);
    CHECK(mismatches(problem, points, mixed_bounds(problem, points), kBatchLanes) == 0);
}

TEST_CASE("a candidate that turns a node far beyond the measured speeds fails in a group as alone", "[batch][bench]") {
    // The drive's speed channel times a scale: at 150 the motor turns at 50 000 rad/s, a
    // stable motion but 150 times the measured 338 rad/s, beyond the 100 times allowed.
    test::TempDir dir;
    const auto file = dir.write("scaled.yaml", "tvid: 1\nname: scaled-drive\ndata: { file: '" +
        (test::source_dir() / "data/aalto_bench/ice_excitation1.csv").string() + "', time: t }\n"
        "model:\n"
        "  nodes: [ { name: motor, J: 7.94e-4 }, { name: load, J: 5.0e-3 } ]\n"
        "  elements:\n"
        "    - { type: speed_source, name: drive, node: motor, input: w_motor, scale: s_w }\n"
        "    - { type: spring_damper, name: shaft, between: [motor, load], k: 30, c: c_s }\n"
        "    - { type: friction, name: loss, node: load, c: 0.001 }\n"
        "inputs: { w_motor: w1 }\n"
        "outputs: { w1: { column: w1, speed: motor }, torque_upper: { column: torque_upper, torque: shaft } }\n"
        "parameters:\n"
        "  s_w: { init: 1, min: 0.5, max: 200 }\n"
        "  c_s: { init: 0.05, min: 0, max: 1 }\n"
        "windows: { estimation: [ { samples: [0, 1000] } ] }\n"
        "initial_state: { kind: steady, node: motor, speed: w1 }\n");
    const Experiment ex = load_experiment(file);
    const IdentificationProblem problem(ex);
    REQUIRE(batch_supported(problem));
    const std::vector<double> points = {1.0, 0.05, 1.02, 0.06, 150.0, 0.05, 0.98, 0.04};
    auto ws = problem.make_workspace();
    CHECK(std::isfinite(problem.cost(points.data(), *ws)));
    CHECK_FALSE(std::isfinite(problem.cost(points.data() + 4, *ws)));
    CHECK(mismatches(problem, points, std::vector<double>(4, kInf), kBatchLanes) == 0);
}

}  // namespace TVID_UNITY_ID

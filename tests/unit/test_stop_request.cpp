// Stopping a fit early (Ctrl-C): the swarm and Levenberg–Marquardt stop at their best
// fully evaluated point when a stop request cuts an evaluation short, and run_fit marks
// the result interrupted with the best so far.
#include <catch2/catch.hpp>
#include <atomic>
#include <cmath>
#include <chrono>
#include <limits>
#include <thread>

#include "support/test_files.hpp"
#include "tvid/estimation/residual_evaluator.hpp"
#include "tvid/estimation/forward_sensitivity.hpp"
#include "tvid/estimation/parallel_evaluator.hpp"
#include "tvid/experiment/experiment.hpp"
#include "tvid/fit/fit_run.hpp"
#include "tvid/optim/levenberg_marquardt.hpp"
#include "tvid/optim/pso.hpp"
#include "tvid/util/stop_request.hpp"

namespace TVID_UNITY_ID {  // unique to this file in a unity build (tests/CMakeLists.txt)

using namespace tvid;

namespace {

// Quadratic bowl around (1, -2); the batch of evaluation number `stop_at` (0-based) is cut
// short like a Ctrl-C in the middle of it: its second half is skipped with +inf.
struct InterruptedBowl : CandidateEvaluator {
    int batches = 0, stop_at = 0;
    bool cut = false;
    void evaluate(const double* c, std::size_t count, std::size_t dim, double* costs) override {
        cut = batches++ == stop_at;
        for (std::size_t i = 0; i < count; ++i) {
            const double dx = c[i * dim] - 1.0, dy = c[i * dim + 1] + 2.0;
            // The skipped half would hold the best candidates if it were scored as 0.
            costs[i] = cut && i >= count / 2 ? std::numeric_limits<double>::infinity() : dx * dx + dy * dy;
        }
    }
    bool stopped() const override { return cut; }
};

// y = a exp(−b t) on t = 0 … 1.9; the evaluation number `stop_at` (residuals or Jacobian,
// 0-based) is refused as if a stop request had arrived before it.
struct InterruptedDecay : LeastSquaresProblem {
    int calls = 0, stop_at = 0;
    bool cut = false;
    std::size_t residual_count() const override { return 20; }
    bool residuals(const double* x, double* r) override {
        if ((cut = calls++ == stop_at)) return false;
        for (int i = 0; i < 20; ++i) r[i] = x[0] * std::exp(-x[1] * 0.1 * i) - 2.0 * std::exp(-1.3 * 0.1 * i);
        return true;
    }
    bool jacobian(const double* x, double* r, Eigen::MatrixXd& J) override {
        if (!residuals(x, r)) return false;
        for (int i = 0; i < 20; ++i) {
            const double e = std::exp(-x[1] * 0.1 * i);
            J(i, 0) = e;
            J(i, 1) = -x[0] * 0.1 * i * e;
        }
        return true;
    }
    bool stopped() const override { return cut; }
};

}  // namespace

TEST_CASE("a swarm stopped in the middle of a batch keeps the best of the last complete iteration", "[stop][pso]") {
    PsoSettings s;
    s.grid = 4;
    s.iterations = 50;
    const SearchBox box{{-10, -10}, {10, 10}, {-5, -5}, {5, 5}};
    InterruptedBowl whole;
    whole.stop_at = -1;
    const PsoSummary reference = run_pso(s, box, whole);

    InterruptedBowl bowl;
    // Batch 6 is iteration 7: no particle moves at k = 1 (zero initial velocities), so
    // that iteration simulates nothing.
    bowl.stop_at = 6;
    const PsoSummary stopped = run_pso(s, box, bowl);
    CHECK(stopped.termination == "stopped");
    CHECK(stopped.iterations == 6);
    REQUIRE(stopped.history.size() == 7);
    // Identical to the uninterrupted swarm up to iteration 6: nothing of batch 6 was used.
    CHECK(stopped.best_cost == reference.history[6].best_cost);
    CHECK(stopped.best_cost > reference.history[7].best_cost);  // iteration 7 would have improved it
    CHECK(stopped.history.back().best_cost == stopped.best_cost);
    CHECK(stopped.evaluations == reference.history[6].evaluations);
    CHECK(stopped.failed_evaluations == 0);
    const double dx = stopped.best[0] - 1.0, dy = stopped.best[1] + 2.0;
    CHECK(dx * dx + dy * dy == stopped.best_cost);
}

TEST_CASE("a swarm stopped during its first batch has no best and says stopped", "[stop][pso]") {
    PsoSettings s;
    s.grid = 3;
    InterruptedBowl bowl;
    bowl.stop_at = 0;
    const PsoSummary stopped = run_pso(s, SearchBox{{-10, -10}, {10, 10}, {-5, -5}, {5, 5}}, bowl);
    CHECK(stopped.termination == "stopped");
    CHECK(stopped.history.empty());
    CHECK_FALSE(std::isfinite(stopped.best_cost));
}

TEST_CASE("Levenberg-Marquardt stopped mid-iteration stays at its last accepted point", "[stop][lm]") {
    LmSettings settings;
    for (int stop_at : {1, 2, 3, 5}) {
        INFO("evaluation " << stop_at << " refused");
        InterruptedDecay whole;
        whole.stop_at = -1;
        LmSettings capped = settings;
        InterruptedDecay problem;
        problem.stop_at = stop_at;
        const LmSummary s = run_levenberg_marquardt(settings, {1.0, 0.5}, {0, 0}, {10, 10}, problem);
        CHECK(s.termination == "stopped");
        CHECK_FALSE(s.success);
        CHECK(s.failed_evaluations == 0);  // a refused evaluation is no model failure
        REQUIRE(s.history.size() == static_cast<std::size_t>(s.iterations) + 1);
        CHECK(s.history.back().best_cost == s.best_cost);
        // The point is fully evaluated: its cost is what the residuals give there.
        Eigen::VectorXd r(20);
        whole.residuals(s.best.data(), r.data());
        CHECK(r.squaredNorm() == Approx(s.best_cost).epsilon(1e-14));
        // And it is where the uninterrupted solver was after the same number of iterations.
        capped.max_iterations = s.iterations;
        const LmSummary same = run_levenberg_marquardt(capped, {1.0, 0.5}, {0, 0}, {10, 10}, whole);
        CHECK(same.best == s.best);
    }
    InterruptedDecay at_start;
    at_start.stop_at = 0;
    const LmSummary s = run_levenberg_marquardt(settings, {1.0, 0.5}, {0, 0}, {10, 10}, at_start);
    CHECK(s.termination == "stopped");
    CHECK(s.failed_evaluations == 0);
    CHECK(s.history.empty());
}

TEST_CASE("the parallel evaluator skips the rest of a batch once the stop flag is set", "[stop]") {
    const Experiment ex = load_experiment(test::source_dir() / "configs/cvt_tipin.yaml");
    const IdentificationProblem problem(ex);
    std::atomic<bool> stop{false};
    ParallelEvaluator evaluator(problem, EvaluatorOptions(2).with_stop(&stop));
    const std::vector<double> x = problem.initial();
    std::vector<double> batch;
    for (int i = 0; i < 4; ++i) batch.insert(batch.end(), x.begin(), x.end());
    std::vector<double> costs(4);
    evaluator.evaluate(batch.data(), 4, x.size(), costs.data());
    CHECK_FALSE(evaluator.stopped());
    for (double c : costs) CHECK(std::isfinite(c));
    stop = true;
    evaluator.evaluate(batch.data(), 4, x.size(), costs.data());
    CHECK(evaluator.stopped());
    for (double c : costs) CHECK(std::isinf(c));

    ResidualEvaluator least_squares(problem, EvaluatorOptions(2).with_jacobian(JacobianKind::sensitivity).with_stop(&stop));
    std::vector<double> r(least_squares.residual_count());
    CHECK_FALSE(least_squares.residuals(x.data(), r.data()));
    CHECK(least_squares.stopped());
    CHECK(least_squares.simulations() == 0);
    stop = false;
    CHECK(least_squares.residuals(x.data(), r.data()));
    CHECK_FALSE(least_squares.stopped());
}

TEST_CASE("a stop request ends the engine's simulations at their next sample, warm-up and sensitivities included",
          "[stop][lm]") {
    // Each engine residual evaluation shoots a two-cycle warm-up before its cycle, and each
    // Jacobian carries the 10 sensitivity columns through both: seconds of work on long
    // windows, which a Ctrl-C must not wait for. A workspace whose flag is up does at most
    // the steps to its next sample.
    const Experiment ex = load_experiment(test::source_dir() / "configs/engine_idle_clean.yaml");
    const IdentificationProblem problem(ex);
    const std::vector<double> x = problem.initial();
    std::atomic<bool> stop{false};

    auto ws = problem.make_workspace();
    ws->stop = &stop;
    std::vector<double> out;
    REQUIRE(problem.residuals(x.data(), *ws, out));
    const std::size_t whole = ws->buffers.rhs_evaluations;
    CHECK(whole > 100000);  // coarse and full shooting, then the scored cycle
    stop = true;
    ws->buffers.rhs_evaluations = 0;
    CHECK_FALSE(problem.residuals(x.data(), *ws, out));
    CHECK(ws->buffers.rhs_evaluations <= 64);  // a coarse step and one sample's 7 substeps, 4 stages each

    const ForwardSensitivity sensitivity(problem);
    auto sws = sensitivity.make_workspace();
    sws->plain->stop = &stop;
    Eigen::MatrixXd J(static_cast<Eigen::Index>(estimation_residual_count(ex)), static_cast<Eigen::Index>(x.size()));
    CHECK_FALSE(sensitivity.jacobian_columns(x.data(), 0, x.size(), *sws, J));
    stop = false;
    CHECK(sensitivity.jacobian_columns(x.data(), 0, x.size(), *sws, J));
    CHECK(problem.residuals(x.data(), *ws, out));
}

TEST_CASE("a stop request raised during an engine evaluation ends it and the least-squares problem says stopped",
          "[stop][lm]") {
    // Six engine cycles scored at once: in an optimized build the residuals take about half
    // a second and a sensitivity Jacobian longer. The flag goes up 20 ms into each, from
    // another thread, after the checks made before a simulation starts.
    const Experiment ex = load_experiment(
        test::source_dir() / "configs/engine_idle_clean.yaml",
        {{"windows.estimation", "[{cycle: 2}, {cycle: 3}, {cycle: 4}, {cycle: 5}, {cycle: 6}, {cycle: 7}]"}});
    const IdentificationProblem problem(ex);
    std::vector<double> x = problem.initial();
    std::atomic<bool> stop{false};
    ResidualEvaluator least_squares(problem, EvaluatorOptions(2).with_jacobian(JacobianKind::sensitivity).with_stop(&stop));
    std::vector<double> r(least_squares.residual_count());
    Eigen::MatrixXd J(static_cast<Eigen::Index>(r.size()), static_cast<Eigen::Index>(x.size()));
    const auto raise_soon = [&stop] {
        return std::thread([&stop] {
            std::this_thread::sleep_for(std::chrono::milliseconds(20));
            stop = true;
        });
    };

    // The Jacobian at the point just evaluated: its column blocks start at once.
    REQUIRE(least_squares.residuals(x.data(), r.data()));
    std::thread raiser = raise_soon();
    const bool jacobian_done = least_squares.jacobian(x.data(), r.data(), J);
    raiser.join();
    CHECK_FALSE(jacobian_done);
    CHECK(least_squares.stopped());

    // Residuals at a new point.
    stop = false;
    x[0] *= 1.01;
    raiser = raise_soon();
    const bool residuals_done = least_squares.residuals(x.data(), r.data());
    raiser.join();
    CHECK_FALSE(residuals_done);
    CHECK(least_squares.stopped());
}

TEST_CASE("run_fit with a stop request returns the best so far, marked interrupted", "[stop][fit]") {
    const Experiment ex = load_experiment(test::source_dir() / "configs/cvt_tipin.yaml",
                                          {{"estimation.pso.start", "latin_hypercube"},
                                           {"estimation.pso.particles", "24"},
                                           {"estimation.pso.iterations", "40"}});
    const IdentificationProblem problem(ex);
    for (const int threads : {1, 2}) {
        std::atomic<bool> stop{false};
        FitOptions options;
        options.threads = threads;
        options.stop = &stop;
        // A Ctrl-C arriving while iteration 7 is reported.
        options.progress = [&stop](const HistoryRow& row) {
            if (row.iteration == 7) stop = true;
            return true;
        };
        const FitResult fit = run_fit(problem, options);
        CHECK(fit.interrupted);
        CHECK(fit.success);
        CHECK(fit.run.termination == "interrupted");
        CHECK(fit.run.termination_type == TerminationType::interrupted);
        CHECK_FALSE(fit.run.converged);
        CHECK(fit.run.iterations == 7);
        REQUIRE(fit.run.history.size() == 8);
        CHECK(fit.run.history.back().best_cost == fit.run.best_cost);
        CHECK(fit.evaluation.cost == Approx(fit.run.best_cost).epsilon(1e-12));
        CHECK_FALSE(fit.uncertainty.available);
        CHECK(fit.uncertainty.problem == "skipped: interrupted");
    }
    // Without a stop request the same options run to the end.
    std::atomic<bool> never{false};
    FitOptions options;
    options.stop = &never;
    const FitResult fit = run_fit(problem, options);
    CHECK_FALSE(fit.interrupted);
    CHECK(fit.run.iterations == 40);
    CHECK(fit.uncertainty.available);
}

TEST_CASE("the process-wide stop request is a lock-free flag", "[stop]") {
    CHECK(stop_request().is_lock_free());
    CHECK_FALSE(stop_requested());
}

}  // namespace TVID_UNITY_ID

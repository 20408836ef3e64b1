#include "tvid/optim/multistart.hpp"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <exception>
#include <limits>
#include <mutex>
#include <stdexcept>
#include <thread>

namespace tvid {

std::vector<double> multistart_points(const MultistartSettings& settings, const SearchBox& box) {
    PsoSettings sample;  // the swarm's seeded Latin hypercube, reused
    sample.start = PsoStart::latin_hypercube;
    sample.particles = settings.starts;
    std::size_t count = 0;
    std::vector<double> points = pso_initial_positions(sample, box, count, settings.seed);
    const std::size_t m = box.lower.size();
    for (std::size_t i = 0; i < points.size(); ++i) points[i] = std::clamp(points[i], box.lower[i % m], box.upper[i % m]);
    return points;
}

MultistartSummary run_multistart(const MultistartSettings& settings, const LmSettings& lm, const SearchBox& box,
                                 int threads, const LeastSquaresFactory& make_problem,
                                 const MultistartProgress& progress) {
    if (settings.starts < 1) throw std::invalid_argument("multistart: at least one start");
    const std::size_t m = box.lower.size();
    const auto n = static_cast<std::size_t>(settings.starts);
    const std::vector<double> points = multistart_points(settings, box);
    LmSettings per_start = lm;
    if (settings.max_iterations) per_start.max_iterations = *settings.max_iterations;

    if (threads <= 0) threads = std::max(1, static_cast<int>(std::thread::hardware_concurrency()));
    MultistartSummary s;
    s.threads = std::min(threads, settings.starts);
    s.threads_per_start = std::max(1, threads / s.threads);
    s.starts.resize(n);
    for (std::size_t i = 0; i < n; ++i) {
        StartResult& r = s.starts[i];
        r.start = static_cast<int>(i) + 1;
        r.initial.assign(points.begin() + static_cast<std::ptrdiff_t>(i * m),
                         points.begin() + static_cast<std::ptrdiff_t>((i + 1) * m));
        r.best = r.initial;
        r.best_cost = r.initial_cost = std::numeric_limits<double>::infinity();
        r.termination_type = TerminationType::not_run;
        r.termination = "not run";
    }

    // Running totals for the progress callback only; the result does not depend on them.
    std::mutex progress_mutex;
    std::atomic<bool> stop{false};
    int steps_so_far = 0;
    long long evaluations_so_far = 0;
    double best_so_far = std::numeric_limits<double>::infinity();
    std::atomic<std::size_t> next{0};
    std::exception_ptr failure;

    auto worker = [&] {
        try {
            for (std::size_t i = next++; i < n && !stop; i = next++) {
                StartResult& r = s.starts[i];
                const std::unique_ptr<LeastSquaresProblem> problem = make_problem(s.threads_per_start);
                long long counted = 0;
                const LmSummary fit = run_levenberg_marquardt(
                    per_start, r.initial, box.lower, box.upper, *problem, [&](const HistoryRow& row) {
                        const long long sims = problem->simulations();
                        const long long now = sims >= 0 ? sims : row.evaluations;
                        HistoryRow own = row;
                        own.evaluations = now;
                        r.history.push_back(own);
                        const std::lock_guard<std::mutex> lock(progress_mutex);
                        evaluations_so_far += now - counted;
                        counted = now;
                        if (row.iteration > 0) ++steps_so_far;
                        best_so_far = std::min(best_so_far, row.best_cost);
                        if (progress && !progress(HistoryRow{steps_so_far, evaluations_so_far, best_so_far})) stop = true;
                        return !stop.load();
                    });
                r.best = fit.best;
                r.best_cost = fit.best_cost;
                r.initial_cost = fit.initial_cost;
                r.iterations = fit.iterations;
                const long long sims = problem->simulations();
                r.evaluations = sims >= 0 ? sims : fit.residual_evaluations + fit.jacobian_evaluations;
                r.failed_evaluations = fit.failed_evaluations;
                r.right_hand_sides = problem->right_hand_sides();
                r.termination_type = fit.termination_type;
                r.termination = fit.termination;
                r.success = fit.success;
            }
        } catch (...) {
            const std::lock_guard<std::mutex> lock(progress_mutex);
            if (!failure) failure = std::current_exception();
            stop = true;
        }
    };
    std::vector<std::thread> pool;
    for (int t = 1; t < s.threads; ++t) pool.emplace_back(worker);
    worker();
    for (std::thread& t : pool) t.join();
    if (failure) std::rethrow_exception(failure);

    // The best start and the history, in start order.
    double best = std::numeric_limits<double>::infinity();
    s.best_cost = best;
    int row = 0;
    for (const StartResult& r : s.starts) {
        if (r.termination_type == TerminationType::not_run) continue;
        for (const HistoryRow& h : r.history) {
            best = std::min(best, h.best_cost);
            s.history.push_back(HistoryRow{row++, s.evaluations + h.evaluations, best});
        }
        s.iterations += r.iterations;
        s.evaluations += r.evaluations;
        s.failed_evaluations += r.failed_evaluations;
        s.right_hand_sides += r.right_hand_sides;
        if (std::isfinite(r.best_cost) && r.best_cost < s.best_cost) {  // a tie keeps the earlier start
            s.best_start = r.start;
            s.best_cost = r.best_cost;
            s.best = r.best;
        }
    }
    // Why starts failed: how many, and the first one's own reason (its LM's account).
    int failed = 0;
    const StartResult* first_failed = nullptr;
    for (const StartResult& r : s.starts)
        if (r.termination_type == TerminationType::start_failed) {
            ++failed;
            if (!first_failed) first_failed = &r;
        }
    const std::string failures =
        failed == 0 ? "" : std::to_string(failed) + " of " + std::to_string(n) + " starts failed; start " +
                               std::to_string(first_failed->start) + ": " + first_failed->termination;
    if (s.best_start == 0) {
        s.best_cost = std::numeric_limits<double>::infinity();
        s.best = s.starts.front().initial;
        s.termination_type = stop ? TerminationType::stopped : TerminationType::all_failed;
        s.termination = stop ? "stopped" : "every start failed" + (failures.empty() ? "" : " (" + failures + ")");
        return s;
    }
    const StartResult& winner = s.starts[static_cast<std::size_t>(s.best_start - 1)];
    s.termination_type = stop ? TerminationType::stopped : winner.termination_type;
    s.termination = stop ? "stopped"
                         : "best of " + std::to_string(n) + " starts: " + winner.termination +
                               (failures.empty() ? "" : " (" + failures + ")");
    s.success = !stop && winner.success;
    return s;
}

}  // namespace tvid

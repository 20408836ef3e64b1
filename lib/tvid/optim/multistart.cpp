#include "tvid/optim/multistart.hpp"

#include "tvid/optim/parameter_scaling.hpp"

#include <algorithm>
#include <cstdint>
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

namespace {

// SplitMix64 (Steele, Lea & Flood 2014): a well-mixed 64-bit stream from any state.
std::uint64_t splitmix64(std::uint64_t& state) {
    std::uint64_t z = (state += 0x9E3779B97F4A7C15ull);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    return z ^ (z >> 31);
}

}  // namespace

std::vector<double> multistart_redraw(const MultistartSettings& settings, const SearchBox& box, int start, int draw) {
    std::uint64_t state = settings.seed;
    state ^= splitmix64(state) + static_cast<std::uint64_t>(start) * 0xD1B54A32D192ED03ull;
    state ^= splitmix64(state) + static_cast<std::uint64_t>(draw) * 0x8CB92BA72F3D8DD7ull;
    const std::size_t m = box.lower.size();
    std::vector<double> point(m);
    for (std::size_t j = 0; j < m; ++j) {
        const double u = static_cast<double>(splitmix64(state) >> 11) * 0x1.0p-53;  // [0, 1)
        const double lo = box.range_lower.empty() ? box.lower[j] : box.range_lower[j];
        const double hi = box.range_upper.empty() ? box.upper[j] : box.range_upper[j];
        point[j] = std::clamp(lo + u * (hi - lo), box.lower[j], box.upper[j]);
    }
    return point;
}

namespace {

// One start: LM from its point, the point redrawn while it cannot be simulated (up to
// settings.max_draws points). `step` sees every LM step with the simulations run so far on
// this start's problem; it returns false to stop.
void run_start(StartResult& r, const MultistartSettings& settings, const LmSettings& per_start, const SearchBox& box,
               LeastSquaresProblem& problem, const std::function<bool(const HistoryRow&, long long)>& step) {
    LmSummary fit;
    long long failed_draws_evaluations = 0;
    bool stopped = false;
    for (r.draws = 1;; ++r.draws) {
        if (r.draws > 1) r.initial = multistart_redraw(settings, box, r.start, r.draws);
        r.history.clear();
        fit = run_levenberg_marquardt(per_start, r.initial, box.lower, box.upper, problem, [&](const HistoryRow& row) {
            const long long sims = problem.simulations();
            HistoryRow own = row;
            own.evaluations = sims >= 0 ? sims : row.evaluations;
            r.history.push_back(own);
            stopped = !step(row, own.evaluations);
            return !stopped;
        });
        // A point that cannot be simulated is redrawn; any other outcome is the start's.
        if (fit.termination_type != TerminationType::start_failed || r.draws >= settings.max_draws || stopped) break;
        failed_draws_evaluations += fit.failed_evaluations;
    }
    r.best = fit.best;
    r.best_cost = fit.best_cost;
    r.initial_cost = fit.initial_cost;
    r.iterations = fit.iterations;
    const long long sims = problem.simulations();
    r.evaluations = sims >= 0 ? sims : fit.residual_evaluations + fit.jacobian_evaluations;
    r.failed_evaluations = fit.failed_evaluations + failed_draws_evaluations;
    r.right_hand_sides = problem.right_hand_sides();
    r.termination_type = fit.termination_type;
    r.termination = fit.termination;
    r.success = fit.success;
}

// The starts before they run: their Latin-hypercube points, not run yet.
std::vector<StartResult> planned_starts(const MultistartSettings& settings, const SearchBox& box) {
    const std::size_t m = box.lower.size();
    const auto n = static_cast<std::size_t>(settings.starts);
    const std::vector<double> points = multistart_points(settings, box);
    std::vector<StartResult> starts(n);
    for (std::size_t i = 0; i < n; ++i) {
        StartResult& r = starts[i];
        r.start = static_cast<int>(i) + 1;
        r.initial.assign(points.begin() + static_cast<std::ptrdiff_t>(i * m),
                         points.begin() + static_cast<std::ptrdiff_t>((i + 1) * m));
        r.best = r.initial;
        r.best_cost = r.initial_cost = std::numeric_limits<double>::infinity();
        r.termination_type = TerminationType::not_run;
        r.termination = "not run";
    }
    return starts;
}

// The best start, the totals and the history, in start order; the termination.
void summarise_starts(MultistartSummary& s, bool stopped) {
    const std::size_t n = s.starts.size();
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
        failed == 0 ? "" : std::to_string(failed) + " of " + std::to_string(n) + " starts failed, each after " +
                               std::to_string(first_failed->draws) + " drawn point" + (first_failed->draws == 1 ? "" : "s") +
                               "; start " + std::to_string(first_failed->start) + ": " + first_failed->termination;
    if (s.best_start == 0) {
        s.best_cost = std::numeric_limits<double>::infinity();
        s.best = s.starts.front().initial;
        s.termination_type = stopped ? TerminationType::stopped : TerminationType::all_failed;
        s.termination = stopped ? "stopped" : "every start failed" + (failures.empty() ? "" : " (" + failures + ")");
        return;
    }
    const StartResult& winner = s.starts[static_cast<std::size_t>(s.best_start - 1)];
    s.termination_type = stopped ? TerminationType::stopped : winner.termination_type;
    s.termination = stopped ? "stopped"
                         : "best of " + std::to_string(n) + " starts: " + winner.termination +
                               (failures.empty() ? "" : " (" + failures + ")");
    s.success = !stopped && winner.success;
}

}  // namespace

MultistartSummary run_multistart(const MultistartSettings& settings, const LmSettings& lm, const SearchBox& box,
                                 int threads, const LeastSquaresFactory& make_problem,
                                 const MultistartProgress& progress) {
    if (settings.starts < 1) throw std::invalid_argument("multistart: at least one start");
    const auto n = static_cast<std::size_t>(settings.starts);
    LmSettings per_start = lm;
    if (settings.max_iterations) per_start.max_iterations = *settings.max_iterations;

    if (threads <= 0) threads = std::max(1, static_cast<int>(std::thread::hardware_concurrency()));
    MultistartSummary s;
    s.threads = std::min(threads, settings.starts);
    s.threads_per_start = std::max(1, threads / s.threads);
    s.starts = planned_starts(settings, box);

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
                const std::unique_ptr<LeastSquaresProblem> problem = make_problem(s.threads_per_start);
                long long counted = 0;
                run_start(s.starts[i], settings, per_start, box, *problem, [&](const HistoryRow& row, long long now) {
                    const std::lock_guard<std::mutex> lock(progress_mutex);
                    evaluations_so_far += now - counted;
                    counted = now;
                    if (row.iteration > 0) ++steps_so_far;
                    best_so_far = std::min(best_so_far, row.best_cost);
                    if (progress && !progress(HistoryRow{steps_so_far, evaluations_so_far, best_so_far})) stop = true;
                    return !stop.load();
                });
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
    summarise_starts(s, stop);
    return s;
}

void to_parameters(const ParameterScaling& scaling, MultistartSummary& s) {
    scaling.best_to_parameters(s);
    for (StartResult& start : s.starts) {
        scaling.map_point(start.initial);
        scaling.map_point(start.best);
    }
}

}  // namespace tvid

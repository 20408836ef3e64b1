#include "tvid/optim/multistart.hpp"

#include "tvid/optim/multistart_race.hpp"
#include "tvid/optim/parameter_scaling.hpp"
#include "tvid/util/splitmix64.hpp"

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

namespace {
constexpr std::size_t kRaceBracket = 32;  // starts that race at once, each holding its problem
}  // namespace

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

// The lowest cost of the starts before `end` (+inf for none).
double lowest_cost(const std::vector<StartResult>& starts, std::size_t end) {
    double best = std::numeric_limits<double>::infinity();
    for (std::size_t i = 0; i < end; ++i)
        if (std::isfinite(starts[i].best_cost)) best = std::min(best, starts[i].best_cost);
    return best;
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

// Runs the starts of a multistart: each on its own problem, the progress callback fed
// running totals (which the result does not depend on), the first exception kept and
// every start stopped after it, one after the other on a pool of threads or raced.
class StartRunner {
public:
    StartRunner(const MultistartSettings& settings, const LmSettings& per_start, const SearchBox& box, int cores,
                const LeastSquaresFactory& make_problem, const MultistartProgress& progress, MultistartSummary& s)
        : settings_(settings), per_start_(per_start), box_(box), make_problem_(make_problem), progress_(progress), s_(s),
          share_(cores) {}

    // Every start on s.threads threads, taking the next start as one ends.
    void pool() {
        const std::size_t n = s_.starts.size();
        std::atomic<std::size_t> next{0};
        const auto worker = [&] {
            share_.job_started();
            guarded([&] {
                for (std::size_t i = next++; i < n && !stop_; i = next++) run_one(i, [](const HistoryRow&) { return true; });
            });
            share_.job_finished();  // the workers still running take up its core
        };
        std::vector<std::thread> threads;
        for (int t = 1; t < s_.threads; ++t) threads.emplace_back(worker);
        worker();
        for (std::thread& t : threads) t.join();
    }

    // Brackets of kRaceBracket starts race one after the other, each start on a thread of
    // its own (waiting at a rung without a core); a bracket's messages measure against the
    // best cost of the brackets before.
    void race() {
        const std::size_t n = s_.starts.size();
        for (std::size_t first = 0; first < n && !stop_; first += kRaceBracket) {
            const std::size_t count = std::min(kRaceBracket, n - first);
            StartRace bracket(count, s_.threads, settings_.race_iterations, per_start_.max_iterations,
                              lowest_cost(s_.starts, first), &share_);
            set_race(&bracket);
            std::vector<std::thread> runners;
            for (std::size_t k = 0; k < count; ++k)
                runners.emplace_back([this, &bracket, first, k] { guarded([&] { run_in_race(bracket, k, first + k); }); });
            for (std::thread& t : runners) t.join();
            set_race(nullptr);
        }
    }

    bool stopped() const { return stop_; }
    void rethrow() const {
        if (failure_) std::rethrow_exception(failure_);
    }

private:
    // Start i as racer k of the bracket: it waits for a core, runs until it ends or the
    // race stops it, and says why it ended.
    void run_in_race(StartRace& bracket, std::size_t k, std::size_t i) {
        if (!bracket.enter(k)) return;
        StartResult& r = s_.starts[i];
        try {
            run_one(i, [&](const HistoryRow& row) { return bracket.step(k, row.iteration, row.best_cost); });
        } catch (...) {
            bracket.leave(k, std::numeric_limits<double>::infinity());
            throw;
        }
        bracket.leave(k, r.best_cost);
        if (!bracket.verdict(k).empty()) {
            r.termination = bracket.verdict(k);
            r.termination_type = TerminationType::raced_out;
            r.success = false;
        }
    }

    // Start i, `gate` asked after each of its LM steps whether it goes on.
    void run_one(std::size_t i, const std::function<bool(const HistoryRow&)>& gate) {
        const std::unique_ptr<LeastSquaresProblem> problem = make_problem_(share_);
        long long counted = 0;
        run_start(s_.starts[i], settings_, per_start_, box_, *problem, [&](const HistoryRow& row, long long now) {
            {
                const std::lock_guard<std::mutex> lock(mutex_);
                evaluations_so_far_ += now - counted;
                counted = now;
                if (row.iteration > 0) ++steps_so_far_;
                best_so_far_ = std::min(best_so_far_, row.best_cost);
                if (progress_ && !progress_(HistoryRow{steps_so_far_, evaluations_so_far_, best_so_far_})) stop_all();
                if (stop_) return false;
            }
            return gate(row);
        });
    }

    void guarded(const std::function<void()>& body) {
        try {
            body();
        } catch (...) {
            const std::lock_guard<std::mutex> lock(mutex_);
            if (!failure_) failure_ = std::current_exception();
            stop_all();
        }
    }

    void stop_all() {  // with mutex_ held
        stop_ = true;
        if (race_) race_->stop();
    }
    void set_race(StartRace* race) {
        const std::lock_guard<std::mutex> lock(mutex_);
        race_ = race;
    }

    const MultistartSettings& settings_;
    const LmSettings& per_start_;
    const SearchBox& box_;
    const LeastSquaresFactory& make_problem_;
    const MultistartProgress& progress_;
    MultistartSummary& s_;
    std::mutex mutex_;
    std::atomic<bool> stop_{false};
    int steps_so_far_ = 0;
    long long evaluations_so_far_ = 0;
    double best_so_far_ = std::numeric_limits<double>::infinity();
    std::exception_ptr failure_;
    StartRace* race_ = nullptr;  // the bracket under way, woken by a stop
    ThreadBudget share_;         // the cores, split over the starts running
};

}  // namespace

MultistartSummary run_multistart(const MultistartSettings& settings, const LmSettings& lm, const SearchBox& box,
                                 int threads, const LeastSquaresFactory& make_problem,
                                 const MultistartProgress& progress) {
    if (settings.starts < 1) throw std::invalid_argument("multistart: at least one start");
    LmSettings per_start = lm;
    if (settings.max_iterations) per_start.max_iterations = *settings.max_iterations;

    if (threads <= 0) threads = std::max(1, static_cast<int>(std::thread::hardware_concurrency()));
    MultistartSummary s;
    s.threads = std::min(threads, settings.starts);
    s.threads_per_start = std::max(1, threads / s.threads);
    s.starts = planned_starts(settings, box);

    StartRunner runner(settings, per_start, box, threads, make_problem, progress, s);
    if (settings.race && settings.starts > 1)
        runner.race();
    else
        runner.pool();
    runner.rethrow();
    summarise_starts(s, runner.stopped());
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

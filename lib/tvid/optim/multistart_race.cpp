#include "tvid/optim/multistart_race.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>

namespace tvid {

namespace {

// A start of the worse half whose cost fell below this fraction of its previous rung's goes on.
constexpr double kStillFalling = 0.5;

// A cost as a ranking key: NaN ranks last.
double rank_key(double cost) { return std::isnan(cost) ? std::numeric_limits<double>::infinity() : cost; }

std::string short_number(double v) {
    char text[32];
    std::snprintf(text, sizeof text, "%.4g", v);
    return text;
}

}  // namespace

StartRace::StartRace(std::size_t count, int cores, int first_rung, int last_iteration, double reference_best,
                     ThreadBudget* share)
    : starts_(count), free_cores_(std::max(1, cores)), first_rung_(std::max(1, first_rung)),
      last_iteration_(last_iteration), reference_best_(rank_key(reference_best)), share_(share) {}

void StartRace::take_core(std::unique_lock<std::mutex>& lock) {
    changed_.wait(lock, [&] { return free_cores_ > 0 || stopped_; });
    if (stopped_) return;
    --free_cores_;
    if (share_) share_->job_started();
}

void StartRace::give_core() {
    ++free_cores_;
    if (share_) share_->job_finished();
    changed_.notify_all();
}

bool StartRace::enter(std::size_t i) {
    std::unique_lock<std::mutex> lock(mutex_);
    take_core(lock);
    if (stopped_) return false;
    starts_[i].phase = Phase::running;
    return true;
}

bool StartRace::step(std::size_t i, int iteration, double cost) {
    Start& s = starts_[i];
    if (iteration == 0) {  // its start (again, for a point drawn anew)
        s.previous_iteration = 0;
        s.previous_cost = rank_key(cost);
    }
    // Rungs only where LM's iteration limit does not end the start first (the shift cannot
    // overflow: the limit is at most 1e6).
    if (s.rung > 30 || rung_iteration(s.rung) >= last_iteration_ || iteration < rung_iteration(s.rung)) return true;
    std::unique_lock<std::mutex> lock(mutex_);
    if (stopped_) return false;
    s.phase = Phase::at_rung;
    s.iteration = iteration;
    s.cost = rank_key(cost);
    give_core();
    decide_if_all_waiting();
    changed_.wait(lock, [&] { return s.phase != Phase::at_rung || stopped_; });
    if (stopped_ || s.phase == Phase::raced_out) return false;
    take_core(lock);
    return !stopped_;
}

void StartRace::leave(std::size_t i, double cost) {
    const std::lock_guard<std::mutex> lock(mutex_);
    Start& s = starts_[i];
    if (s.phase == Phase::running) give_core();  // a raced-out or stopped start holds none
    if (s.phase != Phase::raced_out) s.phase = Phase::ended;
    s.cost = rank_key(cost);
    reference_best_ = std::min(reference_best_, s.cost);
    decide_if_all_waiting();
}

void StartRace::stop() {
    const std::lock_guard<std::mutex> lock(mutex_);
    stopped_ = true;
    changed_.notify_all();
}

// The rung is decided once no start is still on its way to it: ranked by cost (ties to the
// lower start), the better half go on (one more when the count is odd), and of the worse
// half those whose cost fell below half of their previous rung's; the others stop.
void StartRace::decide_if_all_waiting() {
    std::vector<std::size_t> waiting;
    for (std::size_t i = 0; i < starts_.size(); ++i) {
        if (starts_[i].phase == Phase::pending || starts_[i].phase == Phase::running) return;
        if (starts_[i].phase == Phase::at_rung) waiting.push_back(i);
    }
    if (waiting.empty()) return;
    std::stable_sort(waiting.begin(), waiting.end(),
                     [&](std::size_t a, std::size_t b) { return starts_[a].cost < starts_[b].cost; });
    double best = reference_best_;
    for (std::size_t i : waiting) best = std::min(best, starts_[i].cost);
    const std::size_t keep = (waiting.size() + 1) / 2;
    for (std::size_t rank = 0; rank < waiting.size(); ++rank) {
        Start& s = starts_[waiting[rank]];
        if (rank < keep || s.cost < kStillFalling * s.previous_cost) {
            s.phase = Phase::running;  // on its way to the next rung (it takes a core when one is free)
            ++s.rung;
            s.previous_iteration = s.iteration;
            s.previous_cost = s.cost;
            continue;
        }
        s.phase = Phase::raced_out;
        const double fell = s.previous_cost > 0 && std::isfinite(s.previous_cost) ? 1.0 - s.cost / s.previous_cost : 0.0;
        s.verdict = "raced out after " + std::to_string(s.iteration) + " iterations: cost " + short_number(s.cost) +
                    " (down " + short_number(100.0 * fell) + " % since iteration " +
                    std::to_string(s.previous_iteration) + "), the best " + short_number(best) + " (rank " +
                    std::to_string(rank + 1) + " of the " + std::to_string(waiting.size()) + " starts still running)";
    }
    changed_.notify_all();
}

}  // namespace tvid

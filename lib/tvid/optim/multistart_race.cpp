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
    const int rung = s.rung;
    Arrival a{i, iteration, rank_key(cost), s.previous_iteration, s.previous_cost, false};
    a.went_on = certainly_kept(rung, a);
    if (rungs_.size() <= static_cast<std::size_t>(rung)) rungs_.resize(static_cast<std::size_t>(rung) + 1);
    rungs_[static_cast<std::size_t>(rung)].push_back(a);
    if (a.went_on) {  // on to the next rung, keeping its core
        pass_rung(s, a);
        decide_ready_rungs();
        return true;
    }
    s.phase = Phase::at_rung;
    give_core();
    decide_ready_rungs();
    changed_.wait(lock, [&] { return s.phase != Phase::at_rung || stopped_; });
    if (stopped_ || s.phase == Phase::raced_out) return false;
    take_core(lock);
    return !stopped_;
}

void StartRace::leave(std::size_t i, double cost) {
    const std::lock_guard<std::mutex> lock(mutex_);
    Start& s = starts_[i];
    if (s.phase == Phase::running) give_core();  // a raced-out or stopped start holds none
    if (s.phase != Phase::raced_out) {  // a raced-out start's cost is that of its rung (decide)
        s.phase = Phase::ended;
        s.end_cost = rank_key(cost);
    }
    decide_ready_rungs();
}

void StartRace::stop() {
    const std::lock_guard<std::mutex> lock(mutex_);
    stopped_ = true;
    changed_.notify_all();
}

// Its cost fell below kStillFalling of its previous rung's (or its start's): kept at any rank.
bool StartRace::still_falling(const Arrival& a) { return a.cost < kStillFalling * a.previous_cost; }

// Past the rung it arrived at: the next rung measures its fall from here.
void StartRace::pass_rung(Start& s, const Arrival& a) {
    ++s.rung;
    s.previous_iteration = a.iteration;
    s.previous_cost = a.cost;
}

// The rung's order: by cost, ties to the lower start.
bool StartRace::before(const Arrival& a, const Arrival& b) {
    return a.cost < b.cost || (a.cost == b.cost && a.start < b.start);
}

// Whether the rung's decision keeps `a` whatever the starts still on their way bring: it
// is still falling, or even were every start that may yet reach the rung better, it would
// rank within the kept half of those there now.
bool StartRace::certainly_kept(int rung, const Arrival& a) const {
    if (still_falling(a)) return true;
    std::size_t there = 1, ahead = 0, may_come = 0;
    if (static_cast<std::size_t>(rung) < rungs_.size())
        for (const Arrival& b : rungs_[static_cast<std::size_t>(rung)]) {
            ++there;
            if (before(b, a)) ++ahead;
        }
    for (std::size_t j = 0; j < starts_.size(); ++j) {
        const Start& s = starts_[j];
        const bool on_its_way = s.phase == Phase::pending || s.phase == Phase::running || s.phase == Phase::at_rung;
        if (j != a.start && on_its_way && s.rung <= rung && !(s.phase == Phase::at_rung && s.rung == rung)) ++may_come;
    }
    return ahead + may_come < (there + 1) / 2;
}

// Decides every rung, in order, that no start is still on its way to.
void StartRace::decide_ready_rungs() {
    while (!stopped_ && static_cast<std::size_t>(decided_) < rungs_.size()) {
        for (const Start& s : starts_)
            if ((s.phase == Phase::pending || s.phase == Phase::running) && s.rung <= decided_) return;
        decide(decided_++);
    }
}

// The rung's decision: those that reached it ranked by cost, the better half go on (one
// more when the count is odd), and of the worse half those whose cost fell below half of
// their previous rung's; the others stop. The best it names is that of the starts that
// reached the rung or ended before it, and of the races before.
void StartRace::decide(int rung) {
    std::vector<Arrival> there = rungs_[static_cast<std::size_t>(rung)];
    std::sort(there.begin(), there.end(), before);
    double best = reference_best_;
    for (const Arrival& a : there) best = std::min(best, a.cost);
    for (const Start& s : starts_)
        if ((s.phase == Phase::ended || s.phase == Phase::raced_out) && s.rung <= rung) best = std::min(best, s.end_cost);
    const std::size_t keep = (there.size() + 1) / 2;
    for (std::size_t rank = 0; rank < there.size(); ++rank) {
        const Arrival& a = there[rank];
        if (a.went_on) continue;  // kept already (certainly_kept)
        Start& s = starts_[a.start];
        if (rank < keep || still_falling(a)) {
            s.phase = Phase::running;  // on its way to the next rung (it takes a core when one is free)
            pass_rung(s, a);
            continue;
        }
        s.phase = Phase::raced_out;
        s.end_cost = a.cost;
        const double fell = a.previous_cost > 0 && std::isfinite(a.previous_cost) ? 1.0 - a.cost / a.previous_cost : 0.0;
        s.verdict = "raced out after " + std::to_string(a.iteration) + " iterations: cost " + short_number(a.cost) +
                    " (down " + short_number(100.0 * fell) + " % since iteration " +
                    std::to_string(a.previous_iteration) + "), the best " + short_number(best) + " (rank " +
                    std::to_string(rank + 1) + " of the " + std::to_string(there.size()) + " starts still running)";
    }
    changed_.notify_all();
}

}  // namespace tvid

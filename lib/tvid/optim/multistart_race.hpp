#pragma once
// The race of multistart's starts (successive halving, Jamieson & Talwalkar 2016): every
// start runs its Levenberg–Marquardt to the first rung (`race_iterations` trial steps);
// once every start has reached the rung or ended, those that reached it are ranked by
// their cost there and the worse half stop ("raced out"), except those whose cost fell to
// less than half since their previous rung (or their start): still falling that fast, a
// start may yet reach the best basin (LM from a far point often sits for a few steps, then
// drops by orders of magnitude). The rest run on to the next rung, twice as many steps in,
// and so on until one is left, which runs to its end. A start that converges, fails or
// reaches its iteration limit between rungs simply ends.
//
// The decisions depend only on each start's cost at each rung (ties to the lower start
// number), never on which start got there first, so a seed gives the same result for any
// thread count. A start waits at a rung only while its fate is open: one that is still
// falling, or ranks in the better half however the starts still on their way rank, goes
// on at once, as the rung's decision will keep it. A start waits without holding a core:
// `cores` starts run at once and a start at a rung gives its core to another; when fewer
// starts run than there are cores, those running split all of them (ThreadBudget), so the
// last start does not run alone on one.

#include <condition_variable>
#include <cstddef>
#include <mutex>
#include <string>
#include <vector>

#include "tvid/util/thread_budget.hpp"

namespace tvid {

class StartRace {
public:
    /// `count` starts, `cores` of which run at once; the first rung after `first_rung`
    /// trial steps, none at or beyond `last_iteration` (LM's iteration limit);
    /// `reference_best` the lowest cost reached before this race (+inf for none); `share`
    /// (may be null) counts the starts holding a core, so that they split the cores.
    StartRace(std::size_t count, int cores, int first_rung, int last_iteration, double reference_best,
              ThreadBudget* share = nullptr);

    /// Start `i` waits for a core; false when the race was stopped before it got one.
    bool enter(std::size_t i);
    /// After trial step `iteration` of start `i`, its lowest cost so far `cost`: at a rung
    /// it waits for the decision. False when it is raced out (or the race was stopped).
    bool step(std::size_t i, int iteration, double cost);
    /// Start `i` ended (converged, failed, out of iterations, raced out or stopped) with
    /// `cost`; it gives back its core.
    void leave(std::size_t i, double cost);
    /// Every waiting start is woken and stops.
    void stop();

    /// Why start `i` was raced out ("raced out after 8 iterations: ..."); empty when it was not.
    const std::string& verdict(std::size_t i) const { return starts_[i].verdict; }

private:
    enum class Phase { pending, running, at_rung, ended, raced_out };
    struct Start {
        Phase phase = Phase::pending;
        int rung = 0;                 ///< the next rung it reaches (at_rung: the one it waits at; ended: the one it did not reach)
        double previous_cost = 0.0;   ///< at the last rung it passed (or its start)
        int previous_iteration = 0;   ///< that rung's trial step (0: its start)
        double end_cost = 0.0;        ///< ended: its lowest cost
        std::string verdict;
    };
    /// A start at a rung: its cost there, and at the rung before (or its start).
    struct Arrival {
        std::size_t start;
        int iteration;
        double cost;
        int previous_iteration;
        double previous_cost;
        bool went_on;  ///< it did not wait: kept whatever the others bring
    };

    int rung_iteration(int rung) const { return first_rung_ << rung; }
    void take_core(std::unique_lock<std::mutex>& lock);
    void give_core();
    static bool before(const Arrival& a, const Arrival& b);
    static bool still_falling(const Arrival& a);
    static void pass_rung(Start& s, const Arrival& a);
    bool certainly_kept(int rung, const Arrival& a) const;
    void decide_ready_rungs();
    void decide(int rung);

    std::vector<Start> starts_;
    std::vector<std::vector<Arrival>> rungs_;  ///< who reached each rung, in the order they came
    int decided_ = 0;                          ///< the rungs decided so far
    int free_cores_;
    const int first_rung_, last_iteration_;
    const double reference_best_;
    ThreadBudget* share_;
    bool stopped_ = false;
    std::mutex mutex_;
    std::condition_variable changed_;
};

}  // namespace tvid

#pragma once
// A request to stop a long computation early: Ctrl-C (SIGINT) or SIGTERM during a fit.
// The signal handler only sets an atomic flag (async-signal-safe); the optimizers and
// evaluators that are given the flag look at it between simulations and stop, keeping
// the best fully evaluated point, so the caller can still write a complete report.

#include <atomic>

namespace tvid {

/// The process-wide flag the stop signal handlers set. Lock-free, so a handler may set it.
std::atomic<bool>& stop_request();

/// True when a stop has been requested.
inline bool stop_requested() { return stop_request().load(std::memory_order_relaxed); }

/// Marks the stretch in which a stop request also cuts a running simulation short (it
/// ends with SimulationStatus::stopped, a failed candidate the optimizer then stops on):
/// the optimizer's run. Outside it (the evaluation of the final parameters, the report)
/// simulations run to the end, so the report of a stopped fit is still whole. Nests and
/// may be held by several threads (batch jobs) at once.
class InterruptibleSimulations {
public:
    explicit InterruptibleSimulations(bool interruptible);
    ~InterruptibleSimulations();
    InterruptibleSimulations(const InterruptibleSimulations&) = delete;
    InterruptibleSimulations& operator=(const InterruptibleSimulations&) = delete;

private:
    bool interruptible_;
};

/// After a stop request, the stretch in which simulations may still run for a grace
/// period (the evaluation of an interrupted fit's best point, for its report) and are cut
/// short past it, so that a stop never waits for a slow simulation for long.
class SimulationGracePeriod {
public:
    explicit SimulationGracePeriod(double seconds);
    ~SimulationGracePeriod();
    SimulationGracePeriod(const SimulationGracePeriod&) = delete;
    SimulationGracePeriod& operator=(const SimulationGracePeriod&) = delete;
};

/// True when a stop has been requested while some InterruptibleSimulations is held, or
/// past the end of a SimulationGracePeriod: a simulation's step loop looks at it every
/// few thousand steps.
bool simulation_stop_requested();

/// Installs handlers for SIGINT and SIGTERM that set stop_request(). A second signal
/// while a stop is pending ends the process at once with exit status 130 (reports are
/// written atomically, so no file is left torn).
void install_stop_signal_handlers();

}  // namespace tvid

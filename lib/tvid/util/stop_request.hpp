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

/// Installs handlers for SIGINT and SIGTERM that set stop_request(). A second signal
/// while a stop is pending ends the process at once with exit status 130 (reports are
/// written atomically, so no file is left torn).
void install_stop_signal_handlers();

}  // namespace tvid

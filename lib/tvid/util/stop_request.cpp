#include "tvid/util/stop_request.hpp"

#include <signal.h>
#include <chrono>
#include <unistd.h>

namespace tvid {

namespace {

std::atomic<bool> g_stop{false};
static_assert(std::atomic<bool>::is_always_lock_free, "the signal handler needs a lock-free flag");

// Only async-signal-safe operations here: an atomic store and _exit.
extern "C" void on_stop_signal(int) {
    if (g_stop.exchange(true)) ::_exit(130);  // second signal: the user insists
}

}  // namespace

std::atomic<bool>& stop_request() { return g_stop; }

namespace {
std::atomic<int> g_interruptible{0};
std::atomic<long long> g_grace_end_ns{0};  // steady-clock time a grace period ends; 0: none

long long now_ns() {
    return std::chrono::duration_cast<std::chrono::nanoseconds>(std::chrono::steady_clock::now().time_since_epoch())
        .count();
}
}  // namespace

SimulationGracePeriod::SimulationGracePeriod(double seconds) {
    g_grace_end_ns.store(now_ns() + static_cast<long long>(seconds * 1e9), std::memory_order_relaxed);
}

SimulationGracePeriod::~SimulationGracePeriod() { g_grace_end_ns.store(0, std::memory_order_relaxed); }

InterruptibleSimulations::InterruptibleSimulations(bool interruptible) : interruptible_(interruptible) {
    if (interruptible_) g_interruptible.fetch_add(1, std::memory_order_relaxed);
}

InterruptibleSimulations::~InterruptibleSimulations() {
    if (interruptible_) g_interruptible.fetch_sub(1, std::memory_order_relaxed);
}

bool simulation_stop_requested() {
    if (!g_stop.load(std::memory_order_relaxed)) return false;
    if (g_interruptible.load(std::memory_order_relaxed) > 0) return true;
    const long long grace_end = g_grace_end_ns.load(std::memory_order_relaxed);
    return grace_end != 0 && now_ns() > grace_end;
}

void install_stop_signal_handlers() {
    struct sigaction action {};
    action.sa_handler = on_stop_signal;
    sigemptyset(&action.sa_mask);
    action.sa_flags = SA_RESTART;  // a blocking write of the report continues after the signal
    ::sigaction(SIGINT, &action, nullptr);
    ::sigaction(SIGTERM, &action, nullptr);
}

}  // namespace tvid

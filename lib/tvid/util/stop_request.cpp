#include "tvid/util/stop_request.hpp"

#include <signal.h>
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

void install_stop_signal_handlers() {
    struct sigaction action {};
    action.sa_handler = on_stop_signal;
    sigemptyset(&action.sa_mask);
    action.sa_flags = SA_RESTART;  // a blocking write of the report continues after the signal
    ::sigaction(SIGINT, &action, nullptr);
    ::sigaction(SIGTERM, &action, nullptr);
}

}  // namespace tvid

#pragma once
// One line of figures per benchmark case, in the `key=value` form scripts/bench.sh
// collects: wall time, simulations (candidate evaluations) per second, nanoseconds of
// thread time per right-hand side per candidate, threads, the process's peak memory,
// and its CPU time (the figure to compare on a machine shared with other work).

#include <sys/resource.h>

#include <chrono>
#include <cstdio>
#include <string>

namespace tvid::bench {

using Clock = std::chrono::steady_clock;

inline double seconds_since(Clock::time_point t0) {
    return std::chrono::duration<double>(Clock::now() - t0).count();
}

/// Peak resident set of this process so far (getrusage: kilobytes on Linux).
inline double peak_memory_mb() {
    rusage u{};
    getrusage(RUSAGE_SELF, &u);
    return static_cast<double>(u.ru_maxrss) / 1024.0;
}

/// CPU time of this process so far, user + system, all threads (getrusage): unlike the
/// wall time it does not grow when other processes take the cores.
inline double cpu_seconds() {
    rusage u{};
    getrusage(RUSAGE_SELF, &u);
    auto s = [](const timeval& t) { return static_cast<double>(t.tv_sec) + 1e-6 * static_cast<double>(t.tv_usec); };
    return s(u.ru_utime) + s(u.ru_stime);
}

struct BenchRow {
    std::string name;
    double wall_s = 0;
    double simulations = 0;     ///< candidate evaluations (one window simulation each)
    double rhs = 0;             ///< right-hand sides per candidate, summed (0: not counted)
    int threads = 1;
    std::string note;           ///< e.g. the cost reached, for checking runs against each other
};

inline void print_row(const BenchRow& r) {
    const double ns_per_rhs = r.rhs > 0 ? r.wall_s * r.threads * 1e9 / r.rhs : 0.0;
    const double cpu = cpu_seconds();  // the whole process, its setup included
    const double cpu_ns_per_rhs = r.rhs > 0 ? cpu * 1e9 / r.rhs : 0.0;
    std::printf("case=%s wall_s=%.4f sims=%.0f sims_per_s=%.1f rhs=%.0f ns_per_rhs=%.2f threads=%d peak_mb=%.1f "
                "cpu_s=%.3f cpu_ns_per_rhs=%.2f note=%s\n",
                r.name.c_str(), r.wall_s, r.simulations, r.simulations / r.wall_s, r.rhs, ns_per_rhs, r.threads,
                peak_memory_mb(), cpu, cpu_ns_per_rhs, r.note.empty() ? "-" : r.note.c_str());
    std::fflush(stdout);
}

}  // namespace tvid::bench

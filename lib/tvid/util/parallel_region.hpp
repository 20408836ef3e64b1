#pragma once
// No exception escapes a parallel region. An exception that leaves the body of an OpenMP
// region, or the function of a std::thread, ends the process (std::terminate: "terminate
// called after throwing ...", exit 134) instead of reaching the command's one-line report.
// Every parallel region runs its body through a FirstException, and rethrows after the
// region, on the thread that started it:
//
//     FirstException errors;
//     #pragma omp parallel for
//     for (long long i = 0; i < n; ++i) try {
//         work(i);
//     } catch (...) {
//         errors.capture();
//     }
//     errors.rethrow();
//
// (or errors.run([&] { work(i); }) as the loop's body)
// run_on_threads does the same for a pool of std::threads.

#include <atomic>
#include <exception>
#include <mutex>
#include <thread>
#include <vector>

namespace tvid {

class FirstException {
public:
    /// Runs `body`; an exception it throws is kept if it is the region's first, and the
    /// bodies run after it are skipped (the region's result is thrown away anyway).
    template <class Body>
    void run(Body&& body) noexcept {
        if (caught_.load(std::memory_order_relaxed)) return;
        try {
            body();
        } catch (...) {
            keep(std::current_exception());
        }
    }
    /// In a catch (...) handler inside the region: keeps the exception being handled if it
    /// is the region's first.
    void capture() noexcept { keep(std::current_exception()); }
    /// True once a body has thrown.
    bool caught() const { return caught_.load(std::memory_order_acquire); }
    /// After the region: throws the first exception caught, if any.
    void rethrow() {
        if (caught()) std::rethrow_exception(first_);
    }

private:
    void keep(std::exception_ptr e) noexcept {
        const std::lock_guard<std::mutex> lock(mutex_);
        if (!first_) first_ = std::move(e);
        caught_.store(true, std::memory_order_release);
    }
    std::mutex mutex_;
    std::exception_ptr first_;
    std::atomic<bool> caught_{false};
};

/// Runs `work()` on `workers` threads at once (this one and workers − 1 more), waits for
/// all of them, and then throws the first exception any of them threw.
template <class Work>
void run_on_threads(int workers, Work&& work) {
    FirstException errors;
    std::vector<std::thread> pool;
    for (int t = 1; t < workers; ++t) pool.emplace_back([&] { errors.run(work); });
    errors.run(work);
    for (std::thread& t : pool) t.join();
    errors.rethrow();
}

}  // namespace tvid

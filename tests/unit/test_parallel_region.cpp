// No exception escapes a parallel region: it is carried out of an OpenMP loop or a pool
// of threads and thrown on the thread that started it (an escape would end the process).
#include <catch2/catch.hpp>

#include <atomic>
#include <stdexcept>

#include "tvid/io/csv_field.hpp"
#include "tvid/util/parallel_region.hpp"

namespace TVID_UNITY_ID {  // unique to this file in a unity build (tests/CMakeLists.txt)

using tvid::FirstException;

TEST_CASE("an exception in an OpenMP loop is thrown after the region", "[util][parallel]") {
    FirstException errors;
    std::atomic<int> ran{0};
#pragma omp parallel for schedule(dynamic, 1) num_threads(4)
    for (int i = 0; i < 64; ++i) try {
        ++ran;
        if (i == 5) throw std::invalid_argument("no free parameters");
    } catch (...) {
        errors.capture();
    }
    CHECK(errors.caught());
    CHECK_THROWS_WITH(errors.rethrow(), "no free parameters");
    CHECK(ran.load() >= 6);

    FirstException none;
#pragma omp parallel for num_threads(4)
    for (int i = 0; i < 16; ++i) none.run([&] { ++ran; });
    CHECK_FALSE(none.caught());
    CHECK_NOTHROW(none.rethrow());
}

TEST_CASE("an exception on one of a pool's threads is thrown after every thread is joined", "[util][parallel]") {
    std::atomic<int> calls{0};
    CHECK_THROWS_WITH(tvid::run_on_threads(3,
                                           [&] {
                                               if (++calls == 2) throw std::runtime_error("second");
                                           }),
                      "second");
    const int before = calls.load();
    CHECK(before >= 2);  // a thread that starts after the failure skips its work
    CHECK_NOTHROW(tvid::run_on_threads(1, [&] { ++calls; }));
    CHECK(calls.load() == before + 1);
}

TEST_CASE("a CSV text cell is quoted when it holds a comma, a quote or a line break", "[io][csv]") {
    CHECK(tvid::csv_field("Tds") == "Tds");
    CHECK(tvid::csv_field("w, rad_measured [rad/s]") == "\"w, rad_measured [rad/s]\"");
    CHECK(tvid::csv_field("say \"hi\"") == "\"say \"\"hi\"\"\"");
    CHECK(tvid::csv_field("two\nlines") == "\"two\nlines\"");
    CHECK(tvid::csv_field("") == "");
}

}  // namespace TVID_UNITY_ID

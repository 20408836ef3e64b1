// The order spectrum of a signal with known order content: exact on the crank-angle grid,
// and close when the signal is sampled by time at a varying speed.
#include <catch2/catch.hpp>
#include <cmath>
#include <numbers>
#include <vector>

#include "tvid/analysis/order_spectrum.hpp"

namespace TVID_UNITY_ID {  // unique to this file in a unity build (tests/CMakeLists.txt)

using namespace tvid;

namespace {

constexpr double kDeg = std::numbers::pi / 180.0;

// 0.7 + 3 cos(2θ + 0.3) + 1.5 cos(0.5θ − 1) + 0.25 cos(6θ + 2.5), θ the crank angle [rad].
double known_orders(double theta) {
    return 0.7 + 3.0 * std::cos(2.0 * theta + 0.3) + 1.5 * std::cos(0.5 * theta - 1.0) +
           0.25 * std::cos(6.0 * theta + 2.5);
}

// Index of order o in a cycle's spectrum (orders 0.5, 1, 1.5, … for a four-stroke cycle).
std::size_t at_order(double o) { return static_cast<std::size_t>(std::lround(2 * o)) - 1; }

}  // namespace

TEST_CASE("orders of a signal sampled on the crank-angle grid are exact", "[spectra]") {
    // Two cycles of 720° sampled every 0.5°, the last sample the third cycle's start.
    std::vector<double> angle, x;
    for (int j = 0; j <= 2 * 1440; ++j) {
        angle.push_back(0.5 * j);
        x.push_back(known_orders(0.5 * j * kDeg));
    }
    const std::vector<CycleOrderSpectrum> cycles = order_spectrum(angle, x, 0.0);
    REQUIRE(cycles.size() == 2);
    for (std::size_t c = 0; c < 2; ++c) {
        const CycleOrderSpectrum& s = cycles[c];
        CHECK(s.cycle == static_cast<long long>(c));
        CHECK(s.start_deg == Approx(720.0 * static_cast<double>(c)));
        REQUIRE(s.order.size() == 24);  // 0.5 … 12
        CHECK(s.order.front() == 0.5);
        CHECK(s.order.back() == 12.0);
        CHECK(s.mean == Approx(0.7).margin(1e-9));
        // θ counts from each cycle's start; 720° is a whole number of turns for every
        // order but the half orders, whose phase advances by 0.5·4π = 2π per cycle too.
        CHECK(std::abs(s.amplitude[at_order(2)] - 3.0) < 1e-9);
        CHECK(std::abs(s.phase_deg[at_order(2)] - 0.3 / kDeg) < 1e-9);
        CHECK(std::abs(s.amplitude[at_order(0.5)] - 1.5) < 1e-9);
        CHECK(std::abs(s.phase_deg[at_order(0.5)] - (-1.0 / kDeg)) < 1e-9);
        CHECK(std::abs(s.amplitude[at_order(6)] - 0.25) < 1e-9);
        CHECK(std::abs(s.phase_deg[at_order(6)] - 2.5 / kDeg) < 1e-9);
        for (std::size_t i = 0; i < s.order.size(); ++i)
            if (s.order[i] != 2.0 && s.order[i] != 0.5 && s.order[i] != 6.0) CHECK(s.amplitude[i] < 1e-9);
        // Parseval over the cycle: the variance is Σ A²/2.
        CHECK(s.variance == Approx((9.0 + 2.25 + 0.0625) / 2).epsilon(1e-12));
    }
}

TEST_CASE("orders of a signal sampled by time at a varying speed are close", "[spectra]") {
    // Idle at 800 rpm with a 10 % speed ripple at order 2 (the firing of a four-cylinder
    // engine): θ(t) = ω0 t + (0.1 ω0 / (2 ω0)) sin(2 ω0 t), sampled every 50 µs; the signal
    // is periodic in angle, not in time.
    const double omega0 = 800.0 * 2 * std::numbers::pi / 60.0;  // rad/s
    std::vector<double> angle, x;
    for (int i = 0;; ++i) {
        const double t = 50e-6 * i;
        const double theta = omega0 * t + 0.05 * std::sin(2 * omega0 * t) + 30.0 * kDeg;
        if (theta > (2 * 720.0 + 40.0) * kDeg) break;
        angle.push_back(theta / kDeg);
        x.push_back(known_orders(theta));
    }
    // Cycles from 0°: the samples begin at 30°, so cycle 0 is incomplete; cycle 1 is whole.
    const std::vector<CycleOrderSpectrum> cycles = order_spectrum(angle, x, 0.0);
    REQUIRE(cycles.size() == 1);
    const CycleOrderSpectrum& s = cycles[0];
    CHECK(s.cycle == 1);
    CHECK(s.amplitude[at_order(2)] == Approx(3.0).epsilon(1e-3));
    CHECK(s.phase_deg[at_order(2)] == Approx(0.3 / kDeg).margin(0.1));
    CHECK(s.amplitude[at_order(0.5)] == Approx(1.5).epsilon(1e-3));
    CHECK(s.phase_deg[at_order(0.5)] == Approx(-1.0 / kDeg).margin(0.1));
    CHECK(s.amplitude[at_order(6)] == Approx(0.25).epsilon(1e-2));
    CHECK(s.amplitude[at_order(3)] < 1e-3);
}

TEST_CASE("a cycle is whole when its grid lies within one sample of the samples", "[spectra]") {
    // A window that begins one sample after its cycle's start is still the cycle; one
    // that begins two samples after is not.
    std::vector<double> angle, x;
    for (int j = 1; j <= 1440; ++j) {
        angle.push_back(0.5 * j);
        x.push_back(known_orders(0.5 * j * kDeg));
    }
    const std::vector<CycleOrderSpectrum> one_off = order_spectrum(angle, x, 0.0);
    REQUIRE(one_off.size() == 1);
    CHECK(one_off[0].amplitude[at_order(2)] == Approx(3.0).epsilon(1e-2));
    angle.erase(angle.begin());
    x.erase(x.begin());
    CHECK(order_spectrum(angle, x, 0.0).empty());
    // A two-stroke cycle (360°): orders 1, 2, …
    OrderSettings two_stroke;
    two_stroke.cycle_deg = 360.0;
    two_stroke.max_order = 4.0;
    const std::vector<CycleOrderSpectrum> turns = order_spectrum(angle, x, 0.0, two_stroke);
    REQUIRE(turns.size() == 1);
    CHECK(turns[0].cycle == 1);
    CHECK(turns[0].order == std::vector<double>{1.0, 2.0, 3.0, 4.0});
}

TEST_CASE("orders stop below half the samples per cycle", "[spectra]") {
    // 37 samples per 720° cycle resolve bins up to 18 (orders up to 9), not order 12: the
    // higher ones would be aliases of the lower.
    std::vector<double> angle, x;
    for (int j = 0; j <= 2 * 37; ++j) {
        angle.push_back(720.0 * j / 37.0);
        x.push_back(known_orders(angle.back() * kDeg));
    }
    const std::vector<CycleOrderSpectrum> cycles = order_spectrum(angle, x, 0.0);
    REQUIRE(cycles.size() == 2);
    CHECK(cycles[0].order.size() == 18);
    CHECK(cycles[0].order.back() == 9.0);
    // Resampled from 37 samples onto 38 points (at least 2·18 + 2), order 2 is still read to a few per cent.
    CHECK(cycles[0].amplitude[at_order(2)] == Approx(3.0).epsilon(0.05));
}

}  // namespace TVID_UNITY_ID

// An output's detrend and high-pass in the cost (estimation/residual_filter.hpp), against
// hand-derived sequences.
#include <catch2/catch.hpp>
#include <algorithm>
#include <cmath>
#include <numbers>
#include <vector>

#include "tvid/estimation/residual_filter.hpp"

namespace TVID_UNITY_ID {  // unique to this file in a unity build (tests/CMakeLists.txt)

using namespace tvid;

namespace {

std::vector<double> times(std::size_t n, double dt) {
    std::vector<double> t(n);
    for (std::size_t i = 0; i < n; ++i) t[i] = 1.0 + static_cast<double>(i) * dt;
    return t;
}

}  // namespace

TEST_CASE("detrend removes the mean, or the least-squares line, and nothing else", "[estimation][filter]") {
    const std::size_t n = 1000;
    const std::vector<double> t = times(n, 1e-3);
    // 4 whole periods of a sine over the window: orthogonal to a constant.
    const auto wave = [&](std::size_t i) { return std::sin(2 * std::numbers::pi * 4 * (t[i] - t[0]) / (n * 1e-3)); };
    SECTION("mean") {
        std::vector<double> r(n);
        for (std::size_t i = 0; i < n; ++i) r[i] = 3.0 + wave(i);
        filter_residuals(ScoringFilter{Detrend::mean, 0.0}, t.data(), r.data(), n, 1);
        for (std::size_t i = 0; i < n; ++i) CHECK(r[i] == Approx(wave(i)).margin(1e-12));
    }
    SECTION("linear: a line vanishes") {
        std::vector<double> r(n);
        for (std::size_t i = 0; i < n; ++i) r[i] = 2.0 - 7.0 * t[i];
        filter_residuals(ScoringFilter{Detrend::linear, 0.0}, t.data(), r.data(), n, 1);
        for (double v : r) CHECK(v == Approx(0.0).margin(1e-11));
    }
    SECTION("strided: only every third value, one output of three") {
        std::vector<double> r(3 * n, 5.0);
        for (std::size_t i = 0; i < n; ++i) r[3 * i + 1] = 2.0 + 0.5 * t[i];
        filter_residuals(ScoringFilter{Detrend::linear, 0.0}, t.data(), r.data() + 1, n, 3);
        for (std::size_t i = 0; i < n; ++i) {
            CHECK(r[3 * i] == 5.0);
            CHECK(r[3 * i + 1] == Approx(0.0).margin(1e-12));
            CHECK(r[3 * i + 2] == 5.0);
        }
    }
}

TEST_CASE("the high-pass keeps fast content, removes slow drift, and halves its cut-off frequency", "[estimation][filter]") {
    // 1 kHz, 20 s. Forward and backward through the second-order Butterworth: the gain at
    // the cut-off is (1/√2)² = 1/2, zero phase.
    const double dt = 1e-3, fc = 2.0;
    const std::size_t n = 20000;
    const std::vector<double> t = times(n, dt);
    const auto sine = [&](double f, std::size_t i) { return std::sin(2 * std::numbers::pi * f * t[i]); };
    const auto middle_amplitude = [&](const std::vector<double>& r) {  // away from the ends' transients
        double a = 0.0;
        for (std::size_t i = n / 4; i < 3 * n / 4; ++i) a = std::max(a, std::abs(r[i]));
        return a;
    };
    SECTION("at the cut-off: half the amplitude, in phase") {
        std::vector<double> r(n);
        for (std::size_t i = 0; i < n; ++i) r[i] = sine(fc, i);
        filter_residuals(ScoringFilter{Detrend::none, fc}, t.data(), r.data(), n, 1);
        CHECK(middle_amplitude(r) == Approx(0.5).epsilon(2e-3));
        for (std::size_t i = n / 4; i < 3 * n / 4; i += 97) CHECK(r[i] == Approx(0.5 * sine(fc, i)).margin(2e-3));
    }
    SECTION("a slow drift and an offset go, a fast wave stays") {
        std::vector<double> r(n);
        for (std::size_t i = 0; i < n; ++i) r[i] = 4.0 + 3.0 * sine(0.05, i) + sine(40.0, i);
        filter_residuals(ScoringFilter{Detrend::mean, fc}, t.data(), r.data(), n, 1);
        for (std::size_t i = n / 4; i < 3 * n / 4; i += 97) CHECK(r[i] == Approx(sine(40.0, i)).margin(1e-2));
    }
}

}  // namespace TVID_UNITY_ID

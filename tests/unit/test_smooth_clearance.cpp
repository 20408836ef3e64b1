// Yoshida & Takamatsu eqs. 7–11: the smoothed ramp/step and the clearance torque.
#include <catch2/catch.hpp>
#include <cmath>

#include "tvid/model/smooth_clearance.hpp"

namespace TVID_UNITY_ID {  // unique to this file in a unity build (tests/CMakeLists.txt)

using tvid::ClearanceLaw;
using tvid::smooth_ramp;
using tvid::smooth_ramp_step;
using tvid::smooth_step;

TEST_CASE("phi1 and phi2 follow their closed forms where those do not overflow", "[clearance]") {
    for (double sigma : {1.0, 40.0, 1000.0}) {
        for (double x : {-0.3, -0.01, -1e-4, 0.0, 1e-4, 0.01, 0.3}) {
            const double z = sigma * x;
            // ln(1 + e^z) written with log1p so that the reference keeps its digits for z << 0.
            CHECK(smooth_ramp(x, sigma) == Approx(std::log1p(std::exp(z)) / sigma).epsilon(1e-12).margin(1e-300));
            CHECK(smooth_step(x, sigma) == Approx((1 + std::tanh(z)) / 2).epsilon(1e-12).margin(1e-15));
            const auto rs = smooth_ramp_step(x, sigma);
            CHECK(rs.ramp == Approx(smooth_ramp(x, sigma)).epsilon(1e-14));
            CHECK(rs.step == Approx(smooth_step(x, sigma)).epsilon(1e-14).margin(1e-300));
        }
    }
}

TEST_CASE("phi1 and phi2 tend to the unit ramp and step as sigma grows", "[clearance]") {
    CHECK(smooth_ramp(0.0, 1000.0) == Approx(std::log(2.0) / 1000.0));
    CHECK(smooth_step(0.0, 1000.0) == 0.5);
    for (double x : {-0.2, -0.01, 0.01, 0.2}) {
        const double ramp = std::max(x, 0.0), step = x > 0 ? 1.0 : 0.0;
        double previous_gap = 1e300;
        for (double sigma : {1e2, 1e3, 1e4, 1e5}) {
            const double gap = std::abs(smooth_ramp(x, sigma) - ramp) + std::abs(smooth_step(x, sigma) - step);
            CHECK(gap <= previous_gap);
            previous_gap = gap;
        }
        CHECK(previous_gap < 1e-12);
    }
}

TEST_CASE("phi1 and phi2 stay finite and exact for sigma*x up to 1e5 and beyond", "[clearance]") {
    // ln(1 + e^{1e5}) overflows when evaluated literally; the ramp is then exactly x.
    const double sigma = 1e5;
    CHECK(std::isinf(std::log(1 + std::exp(sigma * 1.0))));
    CHECK(smooth_ramp(1.0, sigma) == 1.0);
    CHECK(smooth_ramp(-1.0, sigma) == 0.0);
    CHECK(smooth_step(1.0, sigma) == 1.0);
    CHECK(smooth_step(-1.0, sigma) == 0.0);
    CHECK(smooth_ramp(1e3, 1e6) == 1e3);  // σx = 1e9
    CHECK(std::isfinite(smooth_ramp(-1e3, 1e6)));
    const auto rs = smooth_ramp_step(0.5, 1e5);
    CHECK(rs.ramp == 0.5);
    CHECK(rs.step == 1.0);
}

TEST_CASE("the smoothed clearance torque converges to the impact model of eq. 7", "[clearance]") {
    const double km = 2947.91, kp = 8700.64, cm = 4.10333, cp = 19.2283, mu = 3.55701e-3;
    const ClearanceLaw<double> exact{km, kp, cm, cp, mu, 0.0, false};
    auto eq7 = [&](double th, double rate) {
        if (th < -mu) return km * (th + mu) + cm * rate;
        if (th > mu) return kp * (th - mu) + cp * rate;
        return 0.0;
    };
    for (double th : {-0.02, -0.005, 0.0, 0.002, 0.005, 0.02}) {
        for (double rate : {-3.0, 0.0, 2.0}) {
            CHECK(exact.torque(th, rate) == Approx(eq7(th, rate)).margin(1e-12));
            double previous = 1e300;
            for (double sigma : {1e3, 1e4, 1e5, 1e6}) {
                const ClearanceLaw<double> smooth{km, kp, cm, cp, mu, sigma, true};
                const double err = std::abs(smooth.torque(th, rate) - eq7(th, rate));
                CHECK(err <= previous + 1e-12);
                previous = err;
            }
            // Away from the contact edges the error at σ = 1e6 is below 1e-6 N m.
            if (std::abs(std::abs(th) - mu) > 1e-3) CHECK(previous < 1e-6);
        }
    }
    // Inside the clearance the smoothed torque is tiny but not zero, and G is increasing.
    const ClearanceLaw<double> paper{km, kp, cm, cp, mu, 1132.81, true};
    double last = -1e300;
    for (double th = -0.02; th <= 0.02; th += 1e-4) {
        const double g = paper.torque(th, 0.0);
        CHECK(g > last);
        last = g;
    }
}

TEST_CASE("the clearance law is exact to rounding against long double, however steep", "[clearance]") {
    // The law against the same law in long double, over twists inside, at and beyond the
    // contacts, for steep and soft smoothing.
    const double km = 2947.91, kp = 8700.64, cm = 4.10333, cp = 19.2283;
    auto reference = [&](long double th, long double rate, long double mu, long double sigma) {
        auto ramp = [&](long double x) {
            const long double z = sigma * x;
            return (std::max(z, 0.0L) + std::log1p(std::exp(-std::abs(z)))) / sigma;
        };
        auto step = [&](long double x) { return (1.0L + std::tanh(sigma * x)) / 2.0L; };
        return -km * ramp(-th - mu) + kp * ramp(th - mu) + (cm * step(-th - mu) + cp * step(th - mu)) * rate;
    };
    double worst = 0;
    for (double mu : {0.0, 1e-3, 3.55701e-3, 0.02, 0.1}) {
        for (double sigma : {10.0, 1132.81, 5000.0, 1e4, 1e5}) {
            const ClearanceLaw<double> law{km, kp, cm, cp, mu, sigma, true};
            for (int i = -400; i <= 400; ++i) {
                const double th = 3.0 * mu * i / 400.0 + 1e-5 * i / 400.0;
                const double rate = 0.37 * i / 400.0 - 0.1;
                const long double r = reference(th, rate, mu, sigma);
                const long double scale = std::abs(r) + kp * mu + cp * std::abs(rate) + 1e-12L;
                worst = std::max(worst, static_cast<double>(std::abs(law.torque(th, rate) - r) / scale));
            }
        }
    }
    INFO("largest error " << worst);
    CHECK(worst < 1e-14);
    // σμ = 1e4: e^{−σμ} underflows, yet both contacts stay exact.
    const ClearanceLaw<double> steep{km, kp, cm, cp, 0.1, 1e5, true};
    CHECK(steep.torque(0.2, 1.0) == Approx(kp * 0.1 + cp).epsilon(1e-15));
    CHECK(steep.torque(-0.2, 1.0) == Approx(-km * 0.1 + cm).epsilon(1e-15));
    CHECK(std::abs(steep.torque(0.05, 1.0)) < 1e-300);
}

}  // namespace TVID_UNITY_ID

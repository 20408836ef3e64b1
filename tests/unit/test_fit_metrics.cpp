// Cost, Q-index (Yoshida & Takamatsu eqs. 19–21), fit %, RMSE and residual ratio (the methodology paper Fig. 2b).
#include <catch2/catch.hpp>
#include <cmath>

#include "tvid/analysis/fit_metrics.hpp"

namespace TVID_UNITY_ID {  // unique to this file in a unity build (tests/CMakeLists.txt)

using namespace tvid;

TEST_CASE("fit metrics of a known residual", "[metrics]") {
    const std::vector<double> y{2.0, -4.0, 6.0, 8.0};
    const std::vector<double> ys{1.0, -4.0, 7.0, 10.0};  // e = y* − y = −1, 0, 1, 2
    const FitMetrics m = compute_fit_metrics(y, ys, 1.0);
    CHECK(m.samples == 4);
    CHECK(m.mean_abs_error == Approx(1.0));          // (1 + 0 + 1 + 2) / 4
    CHECK(m.sum_sq_error == Approx(6.0));
    CHECK(m.rmse == Approx(std::sqrt(1.5)));
    CHECK(m.e0 == Approx((1 + 5 + 5 + 7) / 4.0));    // mean |y − offset|
    CHECK(m.q_index == Approx((1 - 1.0 / 4.5) * 100));
    // ȳ = 3, ‖y − ȳ‖² = 1 + 49 + 9 + 25 = 84
    CHECK(m.fit_percent == Approx(100 * (1 - std::sqrt(6.0) / std::sqrt(84.0))));
    // r = (y − y*)/y = 0.5, 0, −1/6, −0.25
    CHECK(m.max_abs_residual_ratio == Approx(0.5));
}

TEST_CASE("a perfect fit has Q = 100 % and zero residual ratio, zero samples are skipped in the ratio", "[metrics]") {
    const std::vector<double> y{0.0, 1.0, 2.0};
    const FitMetrics m = compute_fit_metrics(y, y, 0.0);
    CHECK(m.q_index == 100.0);
    CHECK(m.fit_percent == 100.0);
    CHECK(m.max_abs_residual_ratio == 0.0);
    CHECK(std::isnan(residual_ratio(0.0, 1.0)));
}

TEST_CASE("the residual ratio counts only samples at least 10 % of the window's largest |y|", "[metrics]") {
    // A torque through zero: near its crossing the ratio has a pole (0.5/0.01 = 5000 %).
    const std::vector<double> y{-20.0, -1.5, 0.01, 2.5, 20.0};
    const std::vector<double> ys{-19.0, -1.0, -0.49, 2.0, 21.0};  // y − y* = −1, −0.5, 0.5, 0.5, −1
    CHECK(residual_ratio_floor(y) == Approx(2.0));
    const FitMetrics m = compute_fit_metrics(y, ys, 0.0);
    // Counted: −20 (5 %), 2.5 (20 %) and 20 (5 %); −1.5 and 0.01 are below the floor 2.
    CHECK(m.max_abs_residual_ratio == Approx(0.2));
    CHECK(m.residual_ratio_min_abs_y == 2.5);  // the smallest |y| counted
    CHECK(std::isnan(residual_ratio(0.01, -0.49, 2.0)));
    CHECK(residual_ratio(2.5, 2.0, 2.0) == Approx(0.2));
    // A signal that never comes near zero (the methodology paper's engine speed) loses no sample.
    const std::vector<double> speed{128.0, 131.0, 130.0}, simulated{128.5, 130.0, 130.2};
    CHECK(compute_fit_metrics(speed, simulated, 0.0).max_abs_residual_ratio == Approx(1.0 / 131.0));
}

}  // namespace TVID_UNITY_ID

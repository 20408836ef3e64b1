// Residual whiteness (Ljung–Box, the predictable share of the residual) and the information criteria
// (FPE, AIC, AICc, BIC as the System Identification Toolbox defines them).
#include <catch2/catch.hpp>
#include <Eigen/Dense>
#include <cmath>
#include <numbers>
#include <random>
#include <vector>

#include "tvid/analysis/information_criteria.hpp"
#include "tvid/analysis/residual_whiteness.hpp"

namespace TVID_UNITY_ID {  // unique to this file in a unity build (tests/CMakeLists.txt)

using namespace tvid;

TEST_CASE("white noise is white, and a slow misfit on it is systematic by the share it has", "[statistics]") {
    std::mt19937 random(3);
    std::normal_distribution<double> gauss(0.0, 0.1);
    std::vector<double> noise(5000), misfit(5000);
    for (std::size_t i = 0; i < noise.size(); ++i) {
        noise[i] = gauss(random);
        // A 2 Hz misfit at 1 kHz of RMS 0.33: with the noise, RMSE ≈ 0.345 on noise 0.1.
        misfit[i] = noise[i] + 0.33 * std::sqrt(2.0) * std::sin(2 * std::numbers::pi * 2.0 * static_cast<double>(i) * 1e-3);
    }
    const ResidualWhiteness white = assess_whiteness({noise});
    CHECK(white.samples == 5000);
    CHECK(white.lags == kLjungBoxLags);
    CHECK(white.p_value > 1e-3);
    CHECK(std::abs(white.lag1_correlation) < 0.05);
    CHECK(white.noise_rms == Approx(0.1).epsilon(0.05));
    CHECK(white.systematic_share < 0.05);

    const ResidualWhiteness poor = assess_whiteness({misfit});
    CHECK(poor.p_value < 1e-16);
    // What the AR(20) predictor leaves: the noise, and a few per cent of its own error in
    // reading the slow part from 20 noisy samples.
    CHECK(poor.noise_rms == Approx(0.1).epsilon(0.08));
    // share = 1 − σ_n²/var ≈ 0.33² / (0.33² + 0.1²) ≈ 0.916
    CHECK(poor.systematic_share == Approx(0.33 * 0.33 / (0.33 * 0.33 + 0.01)).epsilon(0.03));
}

TEST_CASE("a misfit near the Nyquist frequency is systematic too", "[statistics]") {
    // A tone at 0.45 of the sampling rate on white noise: the sample-to-sample differences
    // would call it noise; its own past predicts it.
    std::mt19937 random(9);
    std::normal_distribution<double> gauss(0.0, 0.1);
    std::vector<double> e(5000);
    for (std::size_t i = 0; i < e.size(); ++i) e[i] = gauss(random) + 0.2 * std::sin(2 * std::numbers::pi * 0.45 * static_cast<double>(i));
    const ResidualWhiteness w = assess_whiteness({e});
    CHECK(w.p_value < 1e-16);
    CHECK(w.systematic_share == Approx(0.02 / (0.02 + 0.01)).epsilon(0.05));  // tone power 0.2²/2 against 0.1²
}

TEST_CASE("lags never cross a window boundary or a missing sample", "[statistics]") {
    // Each window alternates +1, −1 (ρ1 = −1 within it); two windows end and start on the
    // same sign, which would add a +1 product if the lag crossed.
    std::vector<double> a, b;
    for (int i = 0; i < 50; ++i) {
        a.push_back(i % 2 ? -1.0 : 1.0);
        b.push_back(i % 2 ? 1.0 : -1.0);
    }
    const ResidualWhiteness apart = assess_whiteness({a, b}, 1);
    CHECK(apart.lag1_correlation == Approx(-98.0 / 100.0));  // 49 + 49 products of −1 over Σe² = 100
    std::vector<double> gap = a;
    gap.push_back(std::nan(""));
    gap.insert(gap.end(), b.begin(), b.end());
    CHECK(assess_whiteness({gap}, 1).lag1_correlation == Approx(apart.lag1_correlation));
    CHECK(assess_whiteness({{1.0, 2.0}}).samples == 0);  // too short to judge
}

TEST_CASE("information criteria of a linear least-squares fit match the hand computation", "[statistics]") {
    // y = 2 + 0.5 x + e, fitted by least squares: the residuals are what is left.
    std::mt19937 random(11);
    std::normal_distribution<double> gauss(0.0, 0.3);
    const int n = 200;
    Eigen::MatrixXd X(n, 2);
    Eigen::VectorXd y(n);
    for (int i = 0; i < n; ++i) {
        X(i, 0) = 1.0;
        X(i, 1) = 0.1 * i;
        y(i) = 2.0 + 0.5 * X(i, 1) + gauss(random);
    }
    const Eigen::VectorXd beta = X.colPivHouseholderQr().solve(y);
    const Eigen::MatrixXd e = y - X * beta;
    const InformationCriteria c = information_criteria(e, 2);
    REQUIRE(c.available);
    const double v = e.squaredNorm() / n, np = 2;
    CHECK(c.loss == Approx(v).epsilon(1e-12));
    CHECK(c.fpe == Approx(v * (1 + np / n) / (1 - np / n)).epsilon(1e-12));
    CHECK(c.aic == Approx(n * std::log(v) + 2 * np + n * (std::log(2 * std::numbers::pi) + 1)).epsilon(1e-12));
    CHECK(c.aicc == Approx(c.aic + 2 * np * (np + 1) / (n - np - 1)).epsilon(1e-12));
    CHECK(c.naic == Approx(std::log(v) + 2 * np / n).epsilon(1e-12));
    CHECK(c.bic == Approx(n * std::log(v) + n * (std::log(2 * std::numbers::pi) + 1) + np * std::log(n)).epsilon(1e-12));
    // The raw AIC is −2 log L + 2 n_p of the Gaussian likelihood at the ML variance v.
    double log_l = 0.0;
    for (int i = 0; i < n; ++i) log_l += -0.5 * std::log(2 * std::numbers::pi * v) - e(i) * e(i) / (2 * v);
    CHECK(c.aic == Approx(-2 * log_l + 2 * np).epsilon(1e-12));

    SECTION("two outputs: V is the determinant of the residual covariance") {
        Eigen::MatrixXd e2(n, 2);
        e2.col(0) = e;
        for (int i = 0; i < n; ++i) e2(i, 1) = 0.5 * e(i) + gauss(random);
        const Eigen::Matrix2d s = e2.transpose() * e2 / n;
        const InformationCriteria c2 = information_criteria(e2, 3);
        CHECK(c2.loss == Approx(s(0, 0) * s(1, 1) - s(0, 1) * s(1, 0)).epsilon(1e-12));
        CHECK(c2.aic == Approx(n * std::log(c2.loss) + 6 + 2 * n * (std::log(2 * std::numbers::pi) + 1)).epsilon(1e-12));
    }
}

}  // namespace TVID_UNITY_ID

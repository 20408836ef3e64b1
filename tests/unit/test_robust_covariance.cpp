// The Newey–West long-run covariance (lib/tvid/analysis/robust_covariance.hpp) on the simplest
// least-squares problem, a mean: its sandwich standard error against the known one for white
// and for AR(1) residuals, sqrt((1 + rho)/(1 - rho)) times the white-noise formula.
#include <catch2/catch.hpp>
#include <cmath>
#include <random>

#include "tvid/analysis/robust_covariance.hpp"

namespace TVID_UNITY_ID {  // unique to this file in a unity build (tests/CMakeLists.txt)

using namespace tvid;

namespace {

// Residuals of a mean fitted to AR(1) noise x_t = rho x_{t-1} + e_t (unit innovations),
// and the ratio of the sandwich's standard error to the white-noise one, s / sqrt(N).
double sandwich_over_classic(double rho, std::size_t n, std::size_t& lags, unsigned seed,
                             const std::vector<std::size_t>& windows) {
    std::mt19937_64 rng(seed);
    std::normal_distribution<double> e(0.0, 1.0);
    std::vector<double> x(n);
    double previous = 0.0;
    for (std::size_t t = 0; t < n; ++t) x[t] = previous = rho * previous + e(rng);
    double mean = 0.0;
    for (double v : x) mean += v / static_cast<double>(n);
    std::vector<double> r(n);
    double ssr = 0.0;
    for (std::size_t t = 0; t < n; ++t) {
        r[t] = x[t] - mean;
        ssr += r[t] * r[t];
    }
    const Eigen::MatrixXd js = Eigen::MatrixXd::Ones(static_cast<Eigen::Index>(n), 1);
    const Eigen::MatrixXd s = long_run_score_covariance(js, r, 1, windows, lags);
    const double sandwich = std::sqrt(s(0, 0)) / static_cast<double>(n);           // (JᵀJ)⁻¹ S (JᵀJ)⁻¹
    const double classic = std::sqrt(ssr / static_cast<double>(n - 1) / static_cast<double>(n));
    return sandwich / classic;
}

}  // namespace

TEST_CASE("the sandwich's standard error: the usual one for white residuals, the long-run one for AR(1)", "[uncertainty][robust]") {
    const std::size_t n = 40000;
    std::size_t lags = 0;
    for (const unsigned seed : {1u, 2u, 3u}) {
        INFO("seed " << seed);
        CHECK(sandwich_over_classic(0.0, n, lags, seed, {n}) == Approx(1.0).epsilon(0.1));
        CHECK(lags <= 4);
        // rho 0.8: sqrt(1.8 / 0.2) = 3; Bartlett at Andrews' bandwidth is within about a tenth.
        CHECK(sandwich_over_classic(0.8, n, lags, seed, {n}) == Approx(3.0).epsilon(0.15));
        CHECK(lags > 10);
        CHECK(sandwich_over_classic(-0.5, n, lags, seed, {n}) == Approx(std::sqrt(0.5 / 1.5)).epsilon(0.15));
    }
    // Four windows of a quarter each: the same within the estimate's noise.
    CHECK(sandwich_over_classic(0.8, n, lags, 4, {n / 4, n / 4, n / 4, n / 4}) == Approx(3.0).epsilon(0.15));
}

}  // namespace TVID_UNITY_ID

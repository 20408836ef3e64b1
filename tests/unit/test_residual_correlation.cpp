// The residual analysis of resid(): the autocorrelation of a residual and its
// cross-correlation with each input, with their 99 % bands (analysis/residual_correlation.hpp).
#include <catch2/catch.hpp>
#include <cmath>
#include <random>
#include <vector>

#include "tvid/analysis/residual_correlation.hpp"
#include "tvid/analysis/residual_whiteness.hpp"

namespace TVID_UNITY_ID {  // unique to this file in a unity build (tests/CMakeLists.txt)

using namespace tvid;

namespace {

std::vector<double> white(std::mt19937& random, std::size_t n, double sigma = 1.0) {
    std::normal_distribution<double> gauss(0.0, sigma);
    std::vector<double> out(n);
    for (double& v : out) v = gauss(random);
    return out;
}

// x_i = φ x_{i−1} + w_i, started in its stationary distribution.
std::vector<double> ar1(std::mt19937& random, std::size_t n, double phi) {
    std::normal_distribution<double> gauss(0.0, 1.0);
    std::vector<double> out(n);
    double x = gauss(random) / std::sqrt(1.0 - phi * phi);
    for (double& v : out) {
        v = x;
        x = phi * x + gauss(random);
    }
    return out;
}

}  // namespace

TEST_CASE("white noise lies inside the 99 % bands at about 99 % of the lags", "[correlation]") {
    std::mt19937 random(17);
    int acf_outside = 0, acf_tested = 0, ccf_outside = 0, ccf_tested = 0;
    for (int trial = 0; trial < 200; ++trial) {
        const std::vector<double> e = white(random, 2000), u = white(random, 2000);
        const ResidualCorrelation r = analyse_residual_correlation({{e}}, {{u}});
        REQUIRE(r.lags == kCorrelationLags);
        const CorrelationTest& acf = r.autocorrelation[0];
        REQUIRE(acf.available);
        CHECK(acf.values[0] == 1.0);
        CHECK(acf.band == Approx(2.5758 / std::sqrt(2000.0)).epsilon(1e-4));
        acf_outside += static_cast<int>(acf.outside.size());
        acf_tested += acf.tested(1);
        const CorrelationTest& ccf = r.cross_correlation[0][0];
        CHECK(ccf.lags.front() == -kCorrelationLags);
        CHECK(ccf.lags.back() == kCorrelationLags);
        ccf_outside += static_cast<int>(ccf.outside.size());
        ccf_tested += ccf.tested(-kCorrelationLags);
    }
    CHECK(acf_tested == 200 * 25);
    CHECK(ccf_tested == 200 * 51);
    // 1 % of 5000 lags is 50 (binomial standard deviation 7); of 10200 lags, 102 (10).
    CHECK(acf_outside > 25);
    CHECK(acf_outside < 80);
    CHECK(ccf_outside > 60);
    CHECK(ccf_outside < 150);
}

TEST_CASE("a coloured residual independent of a coloured input stays inside the widened band", "[correlation]") {
    // Both AR(1) with φ = 0.9: the plain ±z/√N band would be crossed at about a quarter of
    // the lags; Ljung's P widens it by sqrt(P) ≈ sqrt((1 + φ²)/(1 − φ²)) ≈ 3.
    std::mt19937 random(23);
    int outside = 0, tested = 0;
    double factor = 0.0;
    for (int trial = 0; trial < 100; ++trial) {
        const std::vector<double> e = ar1(random, 4000, 0.9), u = ar1(random, 4000, 0.9);
        const CorrelationTest t = cross_correlation_test({u}, {e}, kCorrelationLags);
        outside += static_cast<int>(t.outside.size());
        tested += t.tested(-kCorrelationLags);
        factor += t.variance_factor / 100.0;
    }
    CHECK(factor > 5.0);  // (1 + φ²)/(1 − φ²) = 9.5 over infinite lags, less with 25 and the Bartlett weights
    CHECK(factor < 9.5);
    CHECK(static_cast<double>(outside) / tested < 0.03);
}

TEST_CASE("a residual built as a filtered input flags that input and not another", "[correlation]") {
    std::mt19937 random(5);
    const std::size_t n = 3000;
    const std::vector<double> u1 = ar1(random, n, 0.8), u2 = ar1(random, n, 0.8), noise = white(random, n);
    // e = 0.3 · (first-order lag of u1, τ = 5 samples) + noise: a dynamic from u1 the model misses.
    std::vector<double> e(n);
    double lag = 0.0;
    for (std::size_t i = 0; i < n; ++i) {
        lag += (u1[i] - lag) / 5.0;
        e[i] = 0.3 * lag + noise[i];
    }
    const ResidualCorrelation r = analyse_residual_correlation({{e}}, {{u1}, {u2}});
    const CorrelationTest& from_u1 = r.cross_correlation[0][0];
    const CorrelationTest& from_u2 = r.cross_correlation[1][0];
    // Past inputs: the lag's response peaks a few samples after the input.
    CHECK(from_u1.outside_from(0) > 10);
    double largest = 0.0;
    int at = 0;
    for (std::size_t i = 0; i < from_u1.values.size(); ++i)
        if (std::abs(from_u1.values[i]) > largest) largest = std::abs(from_u1.values[i]), at = from_u1.lags[i];
    CHECK(at > 0);
    CHECK(from_u2.outside_from(0) <= 2);
    // The residual is coloured by the lag: its autocorrelation leaves the band too.
    CHECK(r.autocorrelation[0].outside.size() > 3);
}

TEST_CASE("the autocorrelation of an AR(1) residual is φ^k", "[correlation]") {
    std::mt19937 random(41);
    const double phi = 0.6;
    const std::vector<double> e = ar1(random, 100000, phi);
    const CorrelationTest t = autocorrelation_test({e}, 10);
    REQUIRE(t.values.size() == 11);
    for (int k = 0; k <= 10; ++k) CHECK(t.values[static_cast<std::size_t>(k)] == Approx(std::pow(phi, k)).margin(0.015));
    CHECK(t.outside.size() >= 5);  // φ^k above the band 0.008 up to k ≈ 9
}

TEST_CASE("correlations are pooled over windows without crossing a window's end", "[correlation]") {
    // Each window alternates +1, −1; two windows that end and start on the same sign would
    // add a +1 product if a lag crossed from one into the next.
    std::vector<double> a, b;
    for (int i = 0; i < 50; ++i) {
        a.push_back(i % 2 ? -1.0 : 1.0);
        b.push_back(i % 2 ? 1.0 : -1.0);
    }
    const ResidualCorrelation r = analyse_residual_correlation({{a, b}}, {{a, b}}, 1);
    CHECK(r.autocorrelation[0].values[1] == Approx(-98.0 / 100.0));
    // The input equals the residual: r(0) = 1, r(±1) as the autocorrelation's lag 1.
    const CorrelationTest& c = r.cross_correlation[0][0];
    CHECK(c.values[1] == Approx(1.0));
    CHECK(c.values[0] == Approx(-98.0 / 100.0));
    CHECK(c.values[2] == Approx(-98.0 / 100.0));
    // A missing sample ends a run as a window's end does.
    std::vector<double> gap = a;
    gap.push_back(std::nan(""));
    gap.insert(gap.end(), b.begin(), b.end());
    CHECK(autocorrelation_test(finite_runs({gap}), 1).values[1] == Approx(-98.0 / 100.0));
    // The Ljung–Box statistic reads the same autocorrelation.
    CHECK(assess_whiteness({a, b}, 1).lag1_correlation == Approx(r.autocorrelation[0].values[1]));
    CHECK_FALSE(autocorrelation_test({{1.0, 2.0, 3.0}}, 1).available);  // too short to judge
}

}  // namespace TVID_UNITY_ID

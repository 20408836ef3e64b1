// The best-determined combination of weakly determined, correlated parameters.
#include <catch2/catch.hpp>
#include <cmath>

#include "tvid/analysis/determined_combinations.hpp"

namespace TVID_UNITY_ID {  // unique to this file in a unity build (tests/CMakeLists.txt)

using namespace tvid;

namespace {

// Parameters with values `values` and covariance `cov`: the identifiability report flags
// each by its relative standard error (weak above 50 %).
struct Case {
    ParameterUncertainty u;
    IdentifiabilityReport id;
    std::vector<double> values;
};

Case make_case(std::vector<double> values, std::vector<std::vector<double>> cov) {
    Case c;
    c.values = std::move(values);
    c.u.available = true;
    c.u.covariance = cov;
    const std::size_t n = c.values.size();
    c.u.std_error.resize(n);
    c.u.correlation.assign(n, std::vector<double>(n));
    for (std::size_t i = 0; i < n; ++i) c.u.std_error[i] = std::sqrt(cov[i][i]);
    for (std::size_t i = 0; i < n; ++i)
        for (std::size_t j = 0; j < n; ++j) c.u.correlation[i][j] = cov[i][j] / (c.u.std_error[i] * c.u.std_error[j]);
    c.id.available = true;
    for (std::size_t i = 0; i < n; ++i) {
        ParameterIdentifiability p;
        p.name = "p" + std::to_string(i);
        p.value = c.values[i];
        p.std_error = c.u.std_error[i];
        p.judged_std_error = p.relative_std_error = p.std_error / std::abs(p.value);
        p.flag = p.judged_std_error > kWeakRelativeError ? IdentifiabilityFlag::weak : IdentifiabilityFlag::ok;
        c.id.parameters.push_back(p);
    }
    return c;
}

}  // namespace

TEST_CASE("two parameters that trade one for one: their sum is what the data determine", "[identifiability]") {
    // p0 = 1 and p1 = 2, each ± 10 (weak), their sum ± 0.01: var(p0 + p1) = 100 + 100 + 2 cov = 1e-4.
    const double cov01 = (1e-4 - 200.0) / 2.0;
    const Case c = make_case({1.0, 2.0}, {{100.0, cov01}, {cov01, 100.0}});
    const auto groups = determined_combinations(c.u, c.id, c.values);
    REQUIRE(groups.size() == 1);
    const DeterminedCombination& g = groups.front();
    REQUIRE(g.members == std::vector<std::size_t>{0, 1});
    CHECK(g.weights[0] == Approx(1.0).epsilon(1e-6));
    CHECK(g.weights[1] == Approx(1.0).epsilon(1e-6));
    CHECK(g.value == Approx(3.0).epsilon(1e-6));
    CHECK(g.std_error == Approx(0.01).epsilon(1e-3));
    CHECK(g.weakest_correlation == Approx(std::abs(cov01) / 100.0));
}

TEST_CASE("a weighted total: four throws of one damping beside two wheels", "[identifiability]") {
    // y sees only T = a + 4 b + c (a total drag): var(T) tiny, each one weak. Built as the
    // covariance of (a, b, c) = s·(free directions) + the determined direction.
    // Directions orthogonal to w = (1, 4, 1): u1 = (4, -1, 0), u2 = (1, 4, -17) (w·u2 = 0, u1·u2 = 0).
    const double w[3] = {1, 4, 1}, u1[3] = {4, -1, 0}, u2[3] = {1, 4, -17};
    const double big = 1.0, small = 1e-12;
    std::vector<std::vector<double>> cov(3, std::vector<double>(3));
    const double n1 = 17.0, n2 = 306.0, nw = 18.0;  // squared norms
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j)
            cov[i][j] = big * (u1[i] * u1[j] / n1 + u2[i] * u2[j] / n2) + small * w[i] * w[j] / nw;
    const Case c = make_case({0.01, 0.02, 0.025}, cov);
    const auto groups = determined_combinations(c.u, c.id, c.values, 0.0);  // every pair linked
    REQUIRE(groups.size() == 1);
    const DeterminedCombination& g = groups.front();
    REQUIRE(g.members.size() == 3);
    // The largest weight 1: (1/4, 1, 1/4).
    CHECK(g.weights[0] == Approx(0.25).epsilon(1e-6));
    CHECK(g.weights[1] == Approx(1.0).epsilon(1e-6));
    CHECK(g.weights[2] == Approx(0.25).epsilon(1e-6));
    CHECK(g.value == Approx(0.25 * 0.01 + 0.02 + 0.25 * 0.025));
    CHECK(g.std_error == Approx(std::sqrt(small * nw) / 4.0).epsilon(1e-3));  // var(w·p) = small·|w|², over 4
}

TEST_CASE("weak parameters that do not trade against each other form no group", "[identifiability]") {
    const Case c = make_case({1.0, 2.0}, {{100.0, 0.0}, {0.0, 100.0}});
    CHECK(determined_combinations(c.u, c.id, c.values).empty());
    // Nor does one weak parameter correlated with a well-determined one.
    const Case d = make_case({1.0, 2.0}, {{100.0, 0.0999}, {0.0999, 1e-4}});
    CHECK(determined_combinations(d.u, d.id, d.values).empty());
}

}  // namespace TVID_UNITY_ID

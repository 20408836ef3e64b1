// tvid's exp and log1p (lib/tvid/simd/elementary_functions.hpp): within about an ulp of
// the exact value (long double reference), the C library's special values, and the same
// bits in every lane of a pack as for double: the particle swarm's lanes must score each
// candidate exactly as the scalar code does.
#include <catch2/catch.hpp>

#include <bit>
#include <cmath>
#include <cstdint>
#include <limits>
#include <random>
#include <vector>

#include "tvid/simd/elementary_functions.hpp"

namespace TVID_UNITY_ID {  // unique to this file in a unity build (tests/CMakeLists.txt)

using namespace tvid;

namespace {

// |got − exact| in units of the last place of the exact value rounded to double.
double ulps(double got, long double exact) {
    const auto rounded = static_cast<double>(exact);
    if (got == rounded) return 0.0;
    const double magnitude = std::abs(rounded);
    const double ulp = magnitude == 0.0 ? std::numeric_limits<double>::denorm_min()
                                        : std::nextafter(magnitude, std::numeric_limits<double>::infinity()) - magnitude;
    return static_cast<double>(std::abs(static_cast<long double>(got) - exact) / ulp);
}

// The same bits, or both NaN: which NaN operand a fused multiply-add passes on (and so a
// NaN's sign) depends on the instruction form the compiler picks, not on the value.
bool same_bits(double a, double b) {
    return std::bit_cast<std::uint64_t>(a) == std::bit_cast<std::uint64_t>(b) || (std::isnan(a) && std::isnan(b));
}

template <int W>
Pack<W> pack_of(const std::vector<double>& v, std::size_t at) {
    Pack<W> p;
    for (int l = 0; l < W; ++l) p.set(l, v[at + static_cast<std::size_t>(l)]);
    return p;
}

std::vector<double> samples(double lo, double hi, std::size_t n, std::uint64_t seed) {
    std::mt19937_64 rng(seed);
    std::uniform_real_distribution<double> u(lo, hi);
    std::vector<double> v(n);
    for (double& x : v) x = u(rng);
    return v;
}

}  // namespace

TEST_CASE("exp is within about an ulp over its whole range", "[elementary]") {
    double worst = 0.0, worst_at = 0.0;
    for (const auto& range : {std::pair{-745.0, 709.7}, std::pair{-40.0, 0.0}, std::pair{-1e-3, 1e-3}}) {
        for (double x : samples(range.first, range.second, 200000, 7)) {
            const double e = ulps(math::exp(x), std::exp(static_cast<long double>(x)));
            if (e > worst) worst = e, worst_at = x;
        }
    }
    INFO("worst " << worst << " ulp at x = " << worst_at);
    CHECK(worst <= 1.5);
    // Subnormal results are rounded once.
    for (double x : {-708.5, -720.25, -744.0, -745.1})
        CHECK(ulps(math::exp(x), std::exp(static_cast<long double>(x))) <= 1.0);
}

TEST_CASE("exp has the C library's special values", "[elementary]") {
    const double inf = std::numeric_limits<double>::infinity();
    CHECK(math::exp(0.0) == 1.0);
    CHECK(math::exp(-0.0) == 1.0);
    CHECK(math::exp(inf) == inf);
    CHECK(math::exp(-inf) == 0.0);
    CHECK(std::isnan(math::exp(std::numeric_limits<double>::quiet_NaN())));
    CHECK(math::exp(709.78) == std::exp(709.78));
    CHECK(math::exp(709.79) == inf);  // overflow
    CHECK(math::exp(-745.2) == 0.0);  // below half the smallest subnormal
    CHECK(math::exp(1.0) == Approx(std::exp(1.0)).epsilon(2e-16));
}

TEST_CASE("log1p is within an ulp from -1 to large arguments", "[elementary]") {
    double worst = 0.0, worst_at = 0.0;
    std::vector<double> xs = samples(-0.999999, 4.0, 200000, 11);
    for (double x : samples(0.0, 1.0, 100000, 12)) xs.push_back(x);
    for (double x : samples(1.0, 1e300, 20000, 13)) xs.push_back(x);
    for (int k = 1; k < 1070; ++k) xs.push_back(std::ldexp(1.2345, -k));  // tiny, down to subnormal
    for (double x : xs) {
        const double e = ulps(math::log1p(x), std::log1p(static_cast<long double>(x)));
        if (e > worst) worst = e, worst_at = x;
    }
    INFO("worst " << worst << " ulp at x = " << worst_at);
    CHECK(worst <= 1.0);
}

TEST_CASE("log1p has the C library's special values", "[elementary]") {
    const double inf = std::numeric_limits<double>::infinity();
    CHECK(math::log1p(0.0) == 0.0);
    CHECK(std::signbit(math::log1p(-0.0)));
    CHECK(math::log1p(-1.0) == -inf);
    CHECK(std::isnan(math::log1p(-1.5)));
    CHECK(std::isnan(math::log1p(-inf)));
    CHECK(math::log1p(inf) == inf);
    CHECK(std::isnan(math::log1p(std::numeric_limits<double>::quiet_NaN())));
    CHECK(math::log1p(1.0) == Approx(std::log(2.0)).epsilon(2e-16));
}

TEST_CASE("log1p on [0, 1] in pairs sharing a division is within 2 ulp", "[elementary]") {
    const std::vector<double> xs = samples(0.0, 1.0, 200000, 17);
    double worst = 0.0;
    for (std::size_t i = 0; i + 1 < xs.size(); i += 2) {
        double a = 0.0, b = 0.0;
        math::log1p_unit_pair(xs[i], xs[i + 1], a, b);
        worst = std::max({worst, ulps(a, std::log1p(static_cast<long double>(xs[i]))),
                          ulps(b, std::log1p(static_cast<long double>(xs[i + 1])))});
    }
    for (double x : {0.0, 1e-300, 1e-17, 0.41421356237309503, 0.4142135623730951, 1.0}) {
        double a = 0.0, b = 0.0;
        math::log1p_unit_pair(x, 1.0 - x, a, b);
        worst = std::max({worst, ulps(a, std::log1p(static_cast<long double>(x))),
                          ulps(b, std::log1p(static_cast<long double>(1.0 - x)))});
    }
    INFO("worst " << worst << " ulp");
    CHECK(worst <= 2.0);
}

TEST_CASE("sincos is within about an ulp where it reduces by pi/2, the C library's beyond", "[elementary]") {
    double worst_sin = 0.0, worst_cos = 0.0;
    for (const auto& range : {std::pair{-8e5, 8e5}, std::pair{-130.0, 130.0}, std::pair{-1.0, 1.0}}) {
        for (double x : samples(range.first, range.second, 200000, 31)) {
            double s = 0.0, c = 0.0;
            math::sincos(x, s, c);
            worst_sin = std::max(worst_sin, ulps(s, std::sin(static_cast<long double>(x))));
            worst_cos = std::max(worst_cos, ulps(c, std::cos(static_cast<long double>(x))));
        }
    }
    INFO("worst sin " << worst_sin << " ulp, cos " << worst_cos << " ulp");
    CHECK(worst_sin <= 1.5);
    CHECK(worst_cos <= 1.5);
    double s = 0.0, c = 0.0;
    math::sincos(0.0, s, c);
    CHECK((s == 0.0 && c == 1.0));
    math::sincos(-0.0, s, c);
    CHECK(std::signbit(s));
    for (double x : {1e6, -3.7e9, 1e300}) {
        math::sincos(x, s, c);
        CHECK((s == std::sin(x) && c == std::cos(x)));
    }
    math::sincos(std::numeric_limits<double>::infinity(), s, c);
    CHECK((std::isnan(s) && std::isnan(c)));
}

TEST_CASE("every lane of a pack computes the bits of the scalar functions", "[elementary][pack]") {
    std::vector<double> xs = samples(-750.0, 712.0, 4096, 21);
    std::vector<double> ys = samples(-1.2, 3.0, 4096, 22);
    std::vector<double> us = samples(0.0, 1.0, 4096, 23);
    // Special values mixed into the lanes.
    const double specials[] = {0.0, -0.0, std::numeric_limits<double>::infinity(), -1.0, 1e-310,
                               std::numeric_limits<double>::quiet_NaN(), -745.13, 709.78};
    for (std::size_t i = 0; i < 8; ++i) xs[5 * i] = ys[7 * i] = specials[i];
    auto check = [&]<int W>(std::integral_constant<int, W>) {
        std::size_t mismatches = 0;
        for (std::size_t at = 0; at + W <= xs.size(); at += W) {
            const Pack<W> e = math::exp(pack_of<W>(xs, at));
            const Pack<W> l = math::log1p(pack_of<W>(ys, at));
            Pack<W> pa, pb;
            math::log1p_unit_pair(pack_of<W>(us, at), pack_of<W>(us, xs.size() - W - at), pa, pb);
            const Pack<W> f = muladd(pack_of<W>(xs, at), pack_of<W>(ys, at), pack_of<W>(us, at));
            Pack<W> ps, pc;
            math::sincos(pack_of<W>(xs, at) * Pack<W>(1e3), ps, pc);  // some beyond the reduction's range
            for (int lane = 0; lane < W; ++lane) {
                const std::size_t i = at + static_cast<std::size_t>(lane);
                double a = 0.0, b = 0.0;
                math::log1p_unit_pair(us[i], us[xs.size() - W - at + static_cast<std::size_t>(lane)], a, b);
                double s = 0.0, c = 0.0;
                math::sincos(xs[i] * 1e3, s, c);
                if (!same_bits(ps[lane], s) || !same_bits(pc[lane], c)) ++mismatches;
                if (!same_bits(e[lane], math::exp(xs[i])) || !same_bits(l[lane], math::log1p(ys[i])) ||
                    !same_bits(pa[lane], a) || !same_bits(pb[lane], b) || !same_bits(f[lane], muladd(xs[i], ys[i], us[i])))
                    ++mismatches;
            }
        }
        INFO("pack width " << W);
        CHECK(mismatches == 0);
    };
    check(std::integral_constant<int, 2>{});
    check(std::integral_constant<int, 4>{});
    check(std::integral_constant<int, 8>{});
    check(std::integral_constant<int, 16>{});
}

}  // namespace TVID_UNITY_ID

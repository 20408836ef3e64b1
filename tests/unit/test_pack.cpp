// Packs of doubles (lib/tvid/simd/pack.hpp): each lane behaves as the double code does,
// including the corner cases the model code relies on (std::max / std::min with NaN and
// signed zeros, abs of −0, the select that replaces a branch).
#include <catch2/catch.hpp>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <limits>

#include "tvid/simd/pack.hpp"
#include "tvid/simd/select.hpp"

namespace TVID_UNITY_ID {  // unique to this file in a unity build (tests/CMakeLists.txt)

using namespace tvid;

namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr double kInf = std::numeric_limits<double>::infinity();
const double kValues[8] = {-2.5, -0.0, 0.0, 1e-310, 3.0, kNaN, kInf, -kInf};

bool same_bits(double a, double b) { return std::bit_cast<std::uint64_t>(a) == std::bit_cast<std::uint64_t>(b); }

Pack<8> pack(const double (&v)[8], int shift) {
    Pack<8> p;
    for (int l = 0; l < 8; ++l) p.set(l, v[(l + shift) % 8]);
    return p;
}

}  // namespace

TEST_CASE("pack arithmetic, max, min and abs are the double operations lane by lane", "[pack]") {
    for (int shift = 0; shift < 8; ++shift) {
        const Pack<8> a = pack(kValues, 0), b = pack(kValues, shift);
        const Pack<8> sum = a + b, diff = a - b, prod = a * b, quot = a / b, mx = max(a, b), mn = min(a, b);
        const Pack<8> ab = abs(a), neg = -a, root = sqrt(abs(b));
        for (int l = 0; l < 8; ++l) {
            const double x = a[l], y = b[l];
            INFO("lane " << l << ": " << x << ", " << y);
            CHECK(same_bits(sum[l], x + y));
            CHECK(same_bits(diff[l], x - y));
            CHECK(same_bits(prod[l], x * y));
            CHECK(same_bits(quot[l], x / y));
            CHECK(same_bits(mx[l], std::max(x, y)));
            CHECK(same_bits(mn[l], std::min(x, y)));
            CHECK(same_bits(ab[l], std::abs(x)));
            CHECK(same_bits(neg[l], -x));
            CHECK(same_bits(root[l], std::sqrt(std::abs(y))));
        }
    }
}

TEST_CASE("pack comparisons give masks, select chooses lane by lane as the conditional operator", "[pack]") {
    const Pack<8> a = pack(kValues, 0), b = pack(kValues, 3);
    const Mask<8> lt = a < b, ge = a >= b, eq = a == b, ne = a != b;
    const Pack<8> chosen = select(lt, a, b);
    for (int l = 0; l < 8; ++l) {
        const double x = a[l], y = b[l];
        CHECK(lt[l] == (x < y));
        CHECK(ge[l] == (x >= y));
        CHECK(eq[l] == (x == y));
        CHECK(ne[l] == (x != y));
        CHECK(same_bits(chosen[l], select(x < y, x, y)));
    }
    Mask<8> m(false);
    CHECK_FALSE(m.any());
    m.set(5, true);
    CHECK(m.any());
    CHECK_FALSE(m.all());
    CHECK((m | !m).all());
    CHECK_FALSE((m & !m).any());
    const Mask<8> finite = isfinite(a);
    for (int l = 0; l < 8; ++l) CHECK(finite[l] == std::isfinite(a[l]));
}

TEST_CASE("a constant converts to every lane, and lanes are set and read one by one", "[pack]") {
    const Pack<16> c(-0.0);
    for (int l = 0; l < 16; ++l) CHECK(same_bits(c[l], -0.0));
    Pack<16> p(1.0);
    p.set(13, 7.0);
    for (int l = 0; l < 16; ++l) CHECK(p[l] == (l == 13 ? 7.0 : 1.0));
    const Pack<4> two = 2;  // integers convert as for double
    CHECK(two[3] == 2.0);
}

}  // namespace TVID_UNITY_ID

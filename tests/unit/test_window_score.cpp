// The cost's rule for one window (lib/tvid/estimation/window_score.hpp): l1 and l2 on a
// hand-computed example, the stop at a bound, the count of scored samples, and a pack's
// lanes computing exactly the bits of the double code.
#include <catch2/catch.hpp>

#include <bit>
#include <cmath>
#include <cstdint>
#include <limits>
#include <random>
#include <vector>

#include "tvid/estimation/window_score.hpp"
#include "tvid/simd/pack.hpp"

namespace TVID_UNITY_ID {  // unique to this file in a unity build (tests/CMakeLists.txt)

using namespace tvid;

namespace {

bool same_bits(double a, double b) { return std::bit_cast<std::uint64_t>(a) == std::bit_cast<std::uint64_t>(b); }

Window window(std::size_t start, std::size_t first, std::size_t last) {
    Window w;
    w.start = start, w.first = first, w.last = last;
    return w;
}

}  // namespace

TEST_CASE("the window score of l1 is the mean per sample of the summed |e|, of l2 the sum of e²", "[cost]") {
    // Two samples of two outputs: residuals (1, −2) and (0.5, −0.25).
    const double r[] = {1.0, -2.0, 0.5, -0.25};
    WindowScore<double> l1(CostKind::l1, 2), l2(CostKind::l2, 2);
    for (double e : r) {
        l1.add(e);
        l2.add(e);
    }
    CHECK(l1.sum() == 3.75);
    CHECK(l1.share() == 1.875);                 // (1 + 2 + 0.5 + 0.25) / 2 samples
    CHECK(l2.share() == 5.3125);                // 1 + 4 + 0.25 + 0.0625
    CHECK(l1.partial_cost(10.0) == 11.875);     // added to the windows before
    CHECK(l2.partial_cost(10.0) == 15.3125);
    // A window continued from a sum carried over from its earlier piece.
    WindowScore<double> continued(CostKind::l1, 2, 1.0 + 2.0);
    continued.add(0.5);
    continued.add(-0.25);
    CHECK(same_bits(continued.share(), l1.share()));
}

TEST_CASE("the window score reaches a bound once the cost so far does, and the cost is +inf unless finite", "[cost]") {
    WindowScore<double> score(CostKind::l2, 3);
    const double total = 1.0, bound = 2.5;
    score.add(1.0);  // 1 + 1 = 2 < 2.5
    CHECK_FALSE(WindowScore<double>::reached(score.partial_cost(total), bound));
    score.add(0.5);  // 2.25
    CHECK_FALSE(WindowScore<double>::reached(score.partial_cost(total), bound));
    score.add(0.5);  // 2.5: reached (>=)
    CHECK(WindowScore<double>::reached(score.partial_cost(total), bound));
    CHECK_FALSE(WindowScore<double>::reached(std::nan(""), bound));
    CHECK(finished_cost(3.0) == 3.0);
    CHECK(finished_cost(std::nan("")) == std::numeric_limits<double>::infinity());
    CHECK(finished_cost(std::numeric_limits<double>::infinity()) == std::numeric_limits<double>::infinity());
}

TEST_CASE("the scored samples of a window are those after its start from its first scored one on", "[cost]") {
    CHECK(scored_sample_count(window(0, 0, 10)) == 10);    // 1 … 10
    CHECK(scored_sample_count(window(0, 4, 10)) == 7);     // 4 … 10 (a warm-up 0 … 4 scores 4)
    CHECK(scored_sample_count(window(3, 3, 3)) == 0);      // nothing after the start
    CHECK(scored_sample_count(window(5, 10, 50)) == 41);
}

TEST_CASE("a pack's lanes score exactly the bits of the double code", "[cost][simd]") {
    constexpr int W = 16;
    using P = Pack<W>;
    std::mt19937_64 rng(7);
    std::uniform_real_distribution<double> residual(-3.0, 3.0), total(0.0, 5.0);
    for (CostKind kind : {CostKind::l1, CostKind::l2}) {
        const std::size_t samples = 37, outputs = 2;
        std::vector<double> r(samples * outputs * W), totals(W), bounds(W);
        for (double& e : r) e = residual(rng);
        for (int l = 0; l < W; ++l) totals[static_cast<std::size_t>(l)] = total(rng);
        for (int l = 0; l < W; ++l) bounds[static_cast<std::size_t>(l)] = 10.0 + l;
        P pack_total, pack_bound;
        for (int l = 0; l < W; ++l) {
            pack_total.set(l, totals[static_cast<std::size_t>(l)]);
            pack_bound.set(l, bounds[static_cast<std::size_t>(l)]);
        }
        WindowScore<P> pack(kind, samples);
        std::vector<WindowScore<double>> lanes(W, WindowScore<double>(kind, samples));
        for (std::size_t i = 0; i < samples * outputs; ++i) {
            P e;
            for (int l = 0; l < W; ++l) {
                const double e_l = r[i * W + static_cast<std::size_t>(l)];
                e.set(l, e_l);
                lanes[static_cast<std::size_t>(l)].add(e_l);
            }
            pack.add(e);
            const P partial = pack.partial_cost(pack_total);
            const Mask<W> reached = WindowScore<P>::reached(partial, pack_bound);
            for (int l = 0; l < W; ++l) {
                const auto lane = static_cast<std::size_t>(l);
                const double lane_partial = lanes[lane].partial_cost(totals[lane]);
                REQUIRE(same_bits(partial[l], lane_partial));
                REQUIRE(reached[l] == WindowScore<double>::reached(lane_partial, bounds[lane]));
            }
        }
        for (int l = 0; l < W; ++l) {
            REQUIRE(same_bits(pack.sum()[l], lanes[static_cast<std::size_t>(l)].sum()));
            REQUIRE(same_bits(pack.share()[l], lanes[static_cast<std::size_t>(l)].share()));
        }
    }
}

}  // namespace TVID_UNITY_ID

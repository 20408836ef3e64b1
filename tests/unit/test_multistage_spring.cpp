// The multi-stage spring (lib/tvid/model/elements/multistage_spring.hpp): piecewise linear
// torque against twist with smoothed corners, odd or with a negative side of its own; its
// reader's rules.
#include <catch2/catch.hpp>
#include <cmath>
#include <string>
#include <vector>

#include "support/text_element_source.hpp"
#include "tvid/model/dual.hpp"
#include "tvid/model/elements/multistage_spring.hpp"

namespace TVID_UNITY_ID {  // unique to this file in a unity build (tests/CMakeLists.txt)

using namespace tvid;
using tvid::test::read_error;
using tvid::test::TextSource;

namespace {

using Stage = std::pair<double, double>;  // angle, k

MultistageSpringSpec spring(const std::vector<Stage>& positive, const std::vector<Stage>& negative, double s) {
    MultistageSpringSpec e;
    e.stages = static_cast<int>(positive.size());
    e.stages_negative = static_cast<int>(negative.size());
    for (std::size_t i = 0; i < positive.size(); ++i) {
        e.angle[i] = Field::value(positive[i].first);
        e.k[i] = Field::value(positive[i].second);
    }
    for (std::size_t i = 0; i < negative.size(); ++i) {
        e.angle_negative[i] = Field::value(negative[i].first);
        e.k_negative[i] = Field::value(negative[i].second);
    }
    e.smoothing_angle = Field::value(s);
    return e;
}

template <class T>
elements::MultistageSpring::Bound<T> bound_of(const MultistageSpringSpec& s) {
    elements::MultistageSpring::Bound<T> e;
    elements::MultistageSpring::for_each_field([](const FieldInfo&, const Field& f, T& v) { v = T(f.constant); }, s,
                                               e);
    elements::MultistageSpring::bind(s, e);
    return e;
}

// The unsmoothed piecewise linear law of one side: the torque at twist x >= 0.
double piecewise(const std::vector<Stage>& stages, double x) {
    double t = 0.0, previous = 0.0;
    for (const auto& [angle, k] : stages) {
        if (x > angle) t += (k - previous) * (x - angle);
        previous = k;
    }
    return t;
}

// The smoothed law as docs/model-library.md writes it, with std::log1p.
double smoothed(const std::vector<Stage>& positive, const std::vector<Stage>& negative, double s, double x) {
    const auto phi = [s](double y) { return s * (std::max(y / s, 0.0) + std::log1p(std::exp(-std::abs(y / s)))); };
    double t = 0.0, previous = 0.0;
    for (const auto& [angle, k] : positive) {
        t += (k - previous) * phi(x - angle);
        previous = k;
    }
    previous = 0.0;
    for (const auto& [angle, k] : negative) {
        t -= (k - previous) * phi(-x - angle);
        previous = k;
    }
    return t;
}

}  // namespace

TEST_CASE("an odd two-stage spring is piecewise linear away from its corners", "[model][multistage_spring]") {
    const std::vector<Stage> stages = {{0.0, 100.0}, {0.05, 400.0}};
    const auto e = bound_of<double>(spring(stages, {}, 1e-4));
    for (const double x : {0.001, 0.02, 0.049, 0.051, 0.08, 0.3}) {
        INFO("twist " << x);
        // Odd: T(-x) = -T(x), to rounding.
        CHECK(elements::MultistageSpring::spring_torque(e, x) == Approx(piecewise(stages, x)).epsilon(1e-3).margin(1e-3));
        CHECK(elements::MultistageSpring::spring_torque(e, -x) ==
              Approx(-elements::MultistageSpring::spring_torque(e, x)).epsilon(1e-12));
    }
    // The first stage from 0 is k1·θ exactly through zero (φ(x) − φ(−x) = x).
    CHECK(elements::MultistageSpring::spring_torque(e, 1e-6) == Approx(100.0 * 1e-6).epsilon(1e-9));
    CHECK(elements::MultistageSpring::spring_torque(e, 0.0) == 0.0);
}

TEST_CASE("a spring with its own negative side and a free play follows the smoothed law", "[model][multistage_spring]") {
    // 0.01 rad of free play forwards, a soft and a stiff stage; backwards one stiff stage from 0.02 rad.
    const std::vector<Stage> positive = {{0.01, 50.0}, {0.06, 900.0}}, negative = {{0.02, 300.0}};
    const auto e = bound_of<double>(spring(positive, negative, 0.002));
    for (const double x : {-0.2, -0.05, -0.021, -0.01, 0.0, 0.005, 0.03, 0.06, 0.1})
        CHECK(elements::MultistageSpring::spring_torque(e, x) == Approx(smoothed(positive, negative, 0.002, x)).margin(1e-12));
    CHECK(elements::MultistageSpring::spring_torque(e, 0.2) == Approx(50.0 * 0.19 + 850.0 * 0.14).epsilon(1e-6));
    CHECK(elements::MultistageSpring::spring_torque(e, -0.2) == Approx(-300.0 * 0.18).epsilon(1e-6));
}

TEST_CASE("the multi-stage spring's dual-number derivatives match central differences", "[model][multistage_spring]") {
    const std::vector<Stage> positive = {{0.0, 100.0}, {0.05, 400.0}}, negative = {{0.0, 120.0}, {0.04, 600.0}};
    const MultistageSpringSpec s = spring(positive, negative, 0.003);
    for (const double x : {-0.06, -0.041, 0.01, 0.049, 0.07}) {
        // d/dθ, and d/d(k of the positive side's second stage).
        const auto e = bound_of<Dual>(s);
        const double dtheta = elements::MultistageSpring::spring_torque(e, Dual::variable(x, 0, 1)).derivative(0);
        CHECK(dtheta == Approx((smoothed(positive, negative, 0.003, x + 1e-7) - smoothed(positive, negative, 0.003, x - 1e-7)) / 2e-7)
                            .epsilon(1e-5));
        auto ek = bound_of<Dual>(s);
        ek.k[1] = Dual::variable(400.0, 0, 1);
        elements::MultistageSpring::bind(s, ek);
        std::vector<Stage> up = positive, down = positive;
        up[1].second += 1e-3;
        down[1].second -= 1e-3;
        CHECK(elements::MultistageSpring::spring_torque(ek, Dual(x)).derivative(0) ==
              Approx((smoothed(up, negative, 0.003, x) - smoothed(down, negative, 0.003, x)) / 2e-3).epsilon(1e-6).margin(1e-12));
    }
}

TEST_CASE("the multi-stage spring's reader", "[model][multistage_spring]") {
    const auto read = [](TextSource& s, NetworkSpec& n) { read_element<elements::MultistageSpring>(s, "damper", n); };
    NetworkSpec net = tvid::test::two_nodes();
    TextSource given = TextSource::with_lists({{"between", ""}, {"c", "0.5"}},
                     {{"stages", {{{"angle", "0"}, {"k", "p"}}, {{"angle", "0.05"}, {"k", "400"}}}}});
    read_element<elements::MultistageSpring>(given, "damper", net);
    REQUIRE(net.multistage_springs.size() == 1);
    const MultistageSpringSpec& e = net.multistage_springs[0];
    CHECK(e.stages == 2);
    CHECK(e.stages_negative == 0);  // odd
    CHECK(e.k[0].parameter == 0);
    CHECK(e.angle[1].constant == 0.05);
    CHECK(e.smoothing_angle.constant == elements::MultistageSpring::kDefaultSmoothingAngle);

    CHECK(read_error(TextSource(TextSource::Values{{"between", ""}}), read) == "stages: missing");
    CHECK(read_error(TextSource::with_lists({{"between", ""}}, {{"stages", {{{"angle", "0.02"}, {"k", "100"}}, {{"angle", "0.01"}, {"k", "300"}}}}}),
                     read) == "stages[1].angle: must lie beyond the previous stage's 0.02 rad (got 0.01)");
    CHECK(read_error(TextSource::with_lists({{"between", ""}}, {{"stages", {{{"angle", "-0.02"}, {"k", "100"}}}}}), read) ==
          "stages[0].angle: is the twist where the stage begins, counted from zero outwards, and cannot be negative "
          "(got -0.02); give the negative side under stages_negative");
    CHECK(read_error(TextSource::with_lists({{"between", ""}}, {{"stages", {{{"angle", "0"}, {"stiffness", "100"}}}}}), read) ==
          "stages[0].stiffness: unknown key");
    CHECK(read_error(TextSource::with_lists({{"between", ""}}, {{"stages", {{{"angle", "0"}, {"k", "-100"}}}}}), read) ==
          "stages[0].k: cannot be negative: a stage stiffness (got -100)");
}

}  // namespace TVID_UNITY_ID

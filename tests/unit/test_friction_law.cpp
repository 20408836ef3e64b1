// The friction element (lib/tvid/model/elements/friction.hpp): viscous, Coulomb and
// Stribeck friction with a smoothed sign, each direction its own, to ground or between two
// nodes; its reader's rules.
#include <catch2/catch.hpp>
#include <cmath>
#include <string>
#include <vector>

#include "support/text_element_source.hpp"
#include "tvid/model/dual.hpp"
#include "tvid/model/elements/friction.hpp"
#include "tvid/model/network_model.hpp"

namespace TVID_UNITY_ID {  // unique to this file in a unity build (tests/CMakeLists.txt)

using namespace tvid;
using tvid::test::read_error;
using tvid::test::TextSource;

namespace {

struct DryFriction {
    double c = 0.02, c_negative = 0.03, coulomb = 0.5, coulomb_negative = 0.4, breakaway = 0.8, stribeck_speed = 0.5,
           smoothing_speed = 0.05;

    FrictionSpec spec() const {
        FrictionSpec s;
        s.name = "bearing";
        s.c = Field::value(c);
        s.c_negative = Field::value(c_negative);
        s.coulomb = Field::value(coulomb);
        s.coulomb_negative = Field::value(coulomb_negative);
        s.breakaway = Field::value(breakaway);
        s.stribeck_speed = Field::value(stribeck_speed);
        s.smoothing_speed = Field::value(smoothing_speed);
        s.dry = s.asymmetric = s.stribeck = true;
        return s;
    }

    // The law as docs/model-library.md writes it, with std::tanh.
    double expected(double v) const {
        const double s = std::tanh(v / smoothing_speed), p = 0.5 * (1 + s);
        const double cv = c_negative + (c - c_negative) * p;
        const double fc = coulomb_negative + (coulomb - coulomb_negative) * p;
        return cv * v + (fc + (breakaway - coulomb) * std::exp(-(v / stribeck_speed) * (v / stribeck_speed))) * s;
    }
};

template <class T>
elements::Friction::Bound<T> bound_of(const FrictionSpec& s) {
    elements::Friction::Bound<T> e;
    elements::Friction::for_each_field([](const FieldInfo&, const Field& f, T& v) { v = T(f.constant); }, s, e);
    elements::Friction::bind(s, e);
    return e;
}

}  // namespace

TEST_CASE("dry friction follows the smoothed Coulomb-Stribeck law in each direction", "[model][friction]") {
    const DryFriction law;
    const auto e = bound_of<double>(law.spec());
    for (const double v : {-20.0, -3.0, -0.6, -0.05, -1e-3, 0.0, 1e-3, 0.02, 0.3, 2.0, 15.0})
        CHECK(elements::Friction::law(e, v) == Approx(law.expected(v)).margin(1e-14));
    // Far from zero each direction has its own viscous and Coulomb terms.
    CHECK(elements::Friction::law(e, 20.0) == Approx(0.02 * 20.0 + 0.5).epsilon(1e-12));
    CHECK(elements::Friction::law(e, -20.0) == Approx(0.03 * -20.0 - 0.4).epsilon(1e-12));
    // Just past the smoothing width and well below the Stribeck speed, the torque is near the breakaway.
    CHECK(elements::Friction::law(e, 0.2) == Approx(0.02 * 0.2 + 0.5 + 0.3 * std::exp(-0.16)).epsilon(1e-3));
    CHECK(elements::Friction::law(e, 0.0) == 0.0);
}

TEST_CASE("viscous friction alone is c times the speed, to the bit", "[model][friction]") {
    FrictionSpec s;
    s.c = Field::value(0.37);
    const auto e = bound_of<double>(s);
    for (const double v : {-12.5, -1e-3, 0.0, 0.7, 321.0}) CHECK(elements::Friction::law(e, v) == 0.37 * v);
}

TEST_CASE("dry friction's dual-number derivatives match central differences", "[model][friction]") {
    const DryFriction law;
    const FrictionSpec s = law.spec();
    // Each field and the speed as a variable in turn.
    const std::vector<double DryFriction::*> fields = {&DryFriction::c,         &DryFriction::c_negative,
                                                     &DryFriction::coulomb,   &DryFriction::coulomb_negative,
                                                     &DryFriction::breakaway, &DryFriction::stribeck_speed,
                                                     &DryFriction::smoothing_speed};
    for (const double v : {-0.4, -0.03, 0.01, 0.25, 1.5}) {
        for (std::size_t j = 0; j < fields.size(); ++j) {
            INFO("v = " << v << ", field " << j);
            elements::Friction::Bound<Dual> e;
            int k = 0;
            elements::Friction::for_each_field(
                [&](const FieldInfo&, const Field& f, Dual& x) {
                    x = k++ == static_cast<int>(j) ? Dual::variable(f.constant, 0, 1) : Dual(f.constant);
                },
                s, e);
            elements::Friction::bind(s, e);
            const double analytic = elements::Friction::law(e, Dual(v)).derivative(0);
            DryFriction up = law, down = law;
            const double h = 1e-6 * law.*fields[j];
            up.*fields[j] += h;
            down.*fields[j] -= h;
            CHECK(analytic == Approx((up.expected(v) - down.expected(v)) / (2 * h)).epsilon(1e-6).margin(1e-8));  // the difference's rounding: ~1e-16·T/h
        }
        const double analytic = elements::Friction::law(bound_of<Dual>(s), Dual::variable(v, 0, 1)).derivative(0);
        CHECK(analytic == Approx((law.expected(v + 1e-7) - law.expected(v - 1e-7)) / 2e-7).epsilon(1e-5));
    }
}

TEST_CASE("friction between two nodes brakes their relative motion", "[model][friction]") {
    NetworkSpec net = tvid::test::two_nodes();
    FrictionSpec s = DryFriction{}.spec();
    s.b = 1;
    net.frictions.push_back(s);
    NetworkModel<double> model(net);
    const double p[1] = {0.0}, u[1] = {0.0};
    model.set_parameters(p);
    const double x[4] = {0.0, 0.0, 5.0, 4.7};  // a turns 0.3 rad/s faster than b
    double f[4];
    model.derivative(x, u, f);
    const double t = DryFriction{}.expected(0.3);
    CHECK(f[2] == Approx(-t).epsilon(1e-14));  // J = 1
    CHECK(f[3] == Approx(t).epsilon(1e-14));
}

TEST_CASE("the friction reader's rules", "[model][friction]") {
    const auto friction = [](TextSource& s, NetworkSpec& n) { read_element<elements::Friction>(s, "f", n); };
    NetworkSpec net = tvid::test::two_nodes();
    TextSource dry({{"node", "b"}, {"coulomb", "p"}, {"c", "0.1"}});
    read_element<elements::Friction>(dry, "f", net);
    REQUIRE(net.frictions.size() == 1);
    CHECK(net.frictions[0].a == 1);
    CHECK(net.frictions[0].b == kGround);
    CHECK(net.frictions[0].dry);
    CHECK_FALSE(net.frictions[0].asymmetric);
    CHECK(net.frictions[0].coulomb.parameter == 0);
    CHECK(net.frictions[0].coulomb_negative.parameter == 0);  // the same in both directions
    CHECK(net.frictions[0].smoothing_speed.constant == elements::Friction::kDefaultSmoothingSpeed);

    CHECK(read_error(TextSource(TextSource::Values{{"node", "a"}}), friction) == "c: missing");
    CHECK(read_error(TextSource({{"node", "a"}, {"between", ""}, {"c", "1"}}), friction) ==
          "between: friction acts on node: (to ground) or between: [a, b], not both");
    CHECK(read_error(TextSource({{"node", "a"}, {"coulomb", "1"}, {"breakaway", "2"}}), friction) ==
          "breakaway: the Stribeck rise needs both breakaway: [N m] and stribeck_speed: [rad/s]");
    CHECK(read_error(TextSource({{"node", "a"}, {"coulomb", "1"}, {"breakaway", "0.5"}, {"stribeck_speed", "0.1"}}),
                     friction) == "breakaway: must be at least coulomb (1 N m), got 0.5");
    CHECK(read_error(TextSource({{"node", "a"}, {"c", "1"}, {"coulomb_negative", "2"}}), friction) ==
          "coulomb_negative: the backward direction's dry friction needs coulomb: (the forward one's)");
    CHECK(read_error(TextSource({{"node", "a"}, {"c", "1"}, {"smoothing_speed", "0.1"}}), friction) ==
          "smoothing_speed: smooths the sign of dry or direction-dependent friction: give coulomb: or c_negative:");
    CHECK(read_error(TextSource({{"node", "a"}, {"coulomb", "1"}, {"smoothing_speed", "0"}}), friction) ==
          "smoothing_speed: must be positive: a smoothing speed (got 0)");
    CHECK(read_error(TextSource({{"node", "a"}, {"coulomb", "-1"}}), friction) ==
          "coulomb: cannot be negative: a dry friction torque (got -1)");
}

}  // namespace TVID_UNITY_ID

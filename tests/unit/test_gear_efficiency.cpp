// A lossy gear mesh (lib/tvid/model/elements/gear_mesh.hpp, `efficiency`): the output side
// carries n·T·η when a drives b, n·T/η when b drives a, smoothed through zero power.
#include <catch2/catch.hpp>
#include <cmath>

#include "support/text_element_source.hpp"
#include "tvid/model/dual.hpp"
#include "tvid/model/elements/gear_mesh.hpp"
#include "tvid/model/network_model.hpp"

namespace TVID_UNITY_ID {  // unique to this file in a unity build (tests/CMakeLists.txt)

using namespace tvid;
using tvid::test::read_error;
using tvid::test::TextSource;

namespace {

// Two nodes of J = 1 through a lossy mesh of ratio 3 (k = 1000, c = 2, η = p, P_s = 5 W);
// the mesh's torque on either side is an output.
NetworkSpec lossy_stage() {
    NetworkSpec net = tvid::test::two_nodes();
    TextSource given({{"between", ""}, {"ratio", "3"}, {"k", "1000"}, {"c", "2"}, {"efficiency", "p"},
                      {"smoothing_power", "5"}});
    read_element<elements::GearMesh>(given, "stage", net);
    for (const TorqueSide side : {TorqueSide::input, TorqueSide::output}) {
        OutputSpec o;
        o.name = side == TorqueSide::input ? "T_in" : "T_out";
        o.kind = OutputKind::torque;
        o.side = side;
        REQUIRE(net.find_element("stage", o.element));
        net.outputs.push_back(o);
    }
    return net;
}

}  // namespace

TEST_CASE("a lossy mesh loses 1 - eta of the power in the direction it flows", "[model][gear_efficiency]") {
    const NetworkSpec net = lossy_stage();
    NetworkModel<Dual> model(net);
    const double eta = 0.9;
    const Dual p[1] = {Dual::variable(eta, 0, 1)};
    model.set_parameters(p);
    const double u[1] = {0.0};
    struct Case {
        double theta_a, omega_a;
        double factor;  // of n·T on b, far from zero power
    };
    // a twisted ahead of b: T > 0. Turning forwards a drives b (P > 0): η; backwards b drives a: 1/η.
    for (const Case c : {Case{0.01, 50.0, eta}, Case{0.01, -50.0, 1 / eta}, Case{-0.01, 50.0, 1 / eta}, Case{-0.01, -50.0, eta}}) {
        INFO("theta_a " << c.theta_a << ", omega_a " << c.omega_a);
        const Dual x[4] = {Dual(c.theta_a), Dual(0.0), Dual(c.omega_a), Dual(c.omega_a / 3)};
        Dual f[4];
        model.derivative(x, u, f);
        const double t = 1000 * c.theta_a;  // no twist rate
        CHECK(f[2].value() == Approx(-t).epsilon(1e-12));
        CHECK(f[3].value() == Approx(3 * t * c.factor).epsilon(1e-9));
        CHECK(model.output(0, x, u).value() == Approx(t).epsilon(1e-12));
        CHECK(model.output(1, x, u).value() == Approx(3 * t * c.factor).epsilon(1e-9));
        // d(n·T·η^s)/dη = n·T·s·η^(s−1), s = ±1.
        const double s = c.factor == eta ? 1.0 : -1.0;
        CHECK(f[3].derivative(0) == Approx(3 * t * s * std::pow(eta, s - 1)).epsilon(1e-9));
    }
    // Through zero power the factor passes smoothly through 1: at rest it is exactly 1.
    const Dual x[4] = {Dual(0.01), Dual(0.0), Dual(0.0), Dual(0.0)};
    Dual f[4];
    model.derivative(x, u, f);
    CHECK(f[3].value() == Approx(30.0).epsilon(1e-15));
    const Dual slow[4] = {Dual(0.01), Dual(0.0), Dual(0.5), Dual(0.5 / 3)};  // P = 5 W = P_s
    model.derivative(slow, u, f);
    CHECK(f[3].value() == Approx(30.0 * std::pow(eta, std::tanh(1.0))).epsilon(1e-12));
}

TEST_CASE("a lossless mesh is unchanged to the bit, and the efficiency's rules", "[model][gear_efficiency]") {
    NetworkSpec net = tvid::test::two_nodes();
    TextSource given({{"between", ""}, {"ratio", "3"}, {"k", "1000"}, {"c", "2"}});
    read_element<elements::GearMesh>(given, "stage", net);
    CHECK_FALSE(net.gear_meshes[0].lossy);
    NetworkModel<double> model(net);
    const double p[1] = {0.0}, u[1] = {0.0};
    model.set_parameters(p);
    const double x[4] = {0.013, 0.002, 41.0, 13.0};
    double f[4];
    model.derivative(x, u, f);
    const double t = 1000 * (0.013 - 3 * 0.002) + 2 * (41.0 - 3 * 13.0);
    CHECK(f[3] == 3 * t);

    const auto read = [](TextSource& s, NetworkSpec& n) { read_element<elements::GearMesh>(s, "stage", n); };
    CHECK(read_error(TextSource({{"between", ""}, {"ratio", "3"}, {"k", "1"}, {"efficiency", "1.2"}}), read) ==
          "efficiency: must be at most 1 (got 1.2)");
    // Just above 1: the value as given, not rounded to the limit it breaks.
    CHECK(read_error(TextSource({{"between", ""}, {"ratio", "3"}, {"k", "1"}, {"efficiency", "1.0000001"}}), read) ==
          "efficiency: must be at most 1 (got 1.0000001)");
    CHECK(read_error(TextSource({{"between", ""}, {"ratio", "3"}, {"k", "1"}, {"efficiency", "0"}}), read) ==
          "efficiency: must be positive: an efficiency (got 0)");
    CHECK(read_error(TextSource({{"between", ""}, {"ratio", "3"}, {"k", "1"}, {"smoothing_power", "3"}}), read) ==
          "smoothing_power: smooths a lossy mesh's power flow: give efficiency:");
}

}  // namespace TVID_UNITY_ID

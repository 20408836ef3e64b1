// The road load (lib/tvid/model/elements/road_load.hpp): rolling resistance with a smoothed
// sign, a speed-proportional loss and drag, odd in the speed.
#include <catch2/catch.hpp>
#include <cmath>

#include "support/text_element_source.hpp"
#include "tvid/model/dual.hpp"
#include "tvid/model/elements/road_load.hpp"
#include "tvid/model/network_model.hpp"

namespace TVID_UNITY_ID {  // unique to this file in a unity build (tests/CMakeLists.txt)

using namespace tvid;
using tvid::test::read_error;
using tvid::test::TextSource;

TEST_CASE("a road load brakes its node by (a + b|w| + c w^2) sign(w), the sign smoothed", "[model][road_load]") {
    NetworkSpec net = tvid::test::two_nodes();
    TextSource given({{"node", "b"}, {"a", "12"}, {"b", "p"}, {"c", "0.04"}, {"smoothing_speed", "0.2"}});
    read_element<elements::RoadLoad>(given, "road", net);
    REQUIRE(net.road_loads.size() == 1);
    NetworkModel<Dual> model(net);
    const Dual p[1] = {Dual::variable(0.3, 0, 1)};  // b
    model.set_parameters(p);
    const double u[1] = {0.0};
    for (const double w : {-80.0, -1.0, -0.05, 0.0, 0.05, 1.0, 80.0}) {
        INFO("omega " << w);
        const Dual x[4] = {Dual(0.0), Dual(0.0), Dual(0.0), Dual(w)};
        Dual f[4];
        model.derivative(x, u, f);
        const double expected = 12.0 * std::tanh(w / 0.2) + 0.3 * w + 0.04 * w * std::abs(w);
        CHECK(f[3].value() == Approx(-expected).margin(1e-12));  // J = 1
        CHECK(f[3].derivative(0) == Approx(-w).margin(1e-15));   // dT/db = w
        CHECK(f[2].value() == 0.0);
    }
    // Far from standstill it is the quadratic road load of either direction.
    const Dual x[4] = {Dual(0.0), Dual(0.0), Dual(0.0), Dual(-50.0)};
    Dual f[4];
    model.derivative(x, u, f);
    CHECK(f[3].value() == Approx(12.0 + 0.3 * 50 + 0.04 * 2500).epsilon(1e-12));
}

TEST_CASE("the road load's reader", "[model][road_load]") {
    const auto read = [](TextSource& s, NetworkSpec& n) { read_element<elements::RoadLoad>(s, "road", n); };
    CHECK(read_error(TextSource(TextSource::Values{{"node", "a"}}), read) == "a: missing");
    CHECK(read_error(TextSource({{"node", "a"}, {"c", "-0.1"}}), read) == "c: cannot be negative: a drag coefficient (got -0.1)");
    CHECK(read_error(TextSource({{"node", "a"}, {"a", "1"}, {"smoothing_speed", "0"}}), read) ==
          "smoothing_speed: must be positive: a smoothing speed (got 0)");
}

}  // namespace TVID_UNITY_ID

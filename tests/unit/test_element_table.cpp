// The element table (lib/tvid/model/elements/element_kinds.hpp): every kind has a row,
// each kind's field walk visits each field once, the binding hands every field in use to
// the torque formulas, and those formulas give the same bits for double, the dual
// numbers and every lane of a pack.
// Each kind's file describes it: its type name, keys and reader, each field's unit, the
// channel it reads, the outputs it offers and its linearisation; the output kinds' table
// likewise.
#include <catch2/catch.hpp>
#include <cmath>
#include <iterator>
#include <map>
#include <numbers>
#include <functional>
#include <set>
#include <stdexcept>
#include <string>
#include <vector>

#include "tvid/model/dual.hpp"
#include "tvid/model/element_reading.hpp"
#include "tvid/model/elements/composite_kinds.hpp"
#include "tvid/model/network_model.hpp"
#include "tvid/model/network_spec.hpp"
#include "tvid/model/parameter_units.hpp"
#include "tvid/simd/pack.hpp"
#include "support/text_element_source.hpp"

namespace TVID_UNITY_ID {  // unique to this file in a unity build (tests/CMakeLists.txt)

using namespace tvid;
using tvid::test::TextSource;
using tvid::test::read_error;
using tvid::test::two_nodes;

namespace {

// A value of the right size and sign for each field name.
double typical_value(const std::string& field) {
    static const std::map<std::string, double> values = {
        {"k", 120.0},     {"c", 0.5},          {"k_minus", 200.0},     {"k_plus", 300.0}, {"c_minus", 1.5},
        {"c_plus", 2.5},  {"mu", 0.01},        {"sigma", 10.0},       {"ratio", 2.5},    {"offset", 0.3},
        {"scale", 1.7},   {"bore", 0.08},      {"crank_radius", 0.04}, {"rod_length", 0.13},
        {"mass", 0.4},    {"p_atm", 1.0e5},    {"amplitude", 4.0},     {"phase", 0.7},
        {"speed", 12.0},  {"c_negative", 0.7}, {"coulomb", 0.8},        {"coulomb_negative", 0.6},
        {"breakaway", 1.2}, {"stribeck_speed", 6.0}, {"smoothing_speed", 5.0},
        {"a", 3.0},       {"b", 0.2},          {"efficiency", 0.9},    {"smoothing_power", 300.0},
        {"stages.angle", 0.1}, {"stages.k", 150.0}, {"stages_negative.angle", 0.05}, {"stages_negative.k", 90.0},
        {"smoothing_angle", 0.05}, {"setpoint", 0.2}, {"kp", 50.0}, {"kd", 0.8}, {"ki", 5.0}};
    return values.at(field);
}

// Four nodes and at least one element of every kind (the fourth turns at a prescribed
// speed, from input 0 whose slope is input 1, and drives n0 through a spring); every numeric field an element
// uses is a parameter of its own (named ELEMENT.FIELD), and every element's torque is an
// output.
struct AllKindsNetwork {
    NetworkSpec spec;
    std::vector<double> p;
    CrankAngleChannels pressure;

    AllKindsNetwork() {
        spec.preset = "custom";
        spec.input_names = {"u"};
        spec.angle_input_names = {"p_cyl"};
        for (const char* name : {"n0", "n1", "n2", "n3", "n4"}) {
            spec.parameter_names.push_back(std::string("J_") + name);
            p.push_back(0.05);
            spec.nodes.push_back(NodeSpec{name, Field::param(static_cast<int>(p.size() - 1)), false});
        }
        spec.spring_dampers.push_back(SpringDamperSpec{"spring", 0, 1, {}, {}});
        spec.clearances.push_back(ClearanceSpec{"stop", 1, kGround, {}, {}, {}, {}, {}, {}, true});
        spec.frictions.push_back(FrictionSpec{"bearing", 2, {}});
        FrictionSpec slip{"slip", 2, {}, 1};  // dry, Stribeck and each direction its own, between n2 and n1
        slip.dry = slip.asymmetric = slip.stribeck = true;
        spec.frictions.push_back(slip);
        GearMeshSpec stiff_gear{"stiff_gear", 1, 2, {}, {}, {}, false, {}, {}, {}, {}, {}, {}, true};
        GearMeshSpec loose_gear{"loose_gear", 0, 2, {}, {}, {}, true, {}, {}, {}, {}, {}, {}, true};
        GearMeshSpec lossy_gear{"lossy_gear", 0, 1, {}, {}, {}, false, {}, {}, {}, {}, {}, {}, true};
        lossy_gear.lossy = true;
        spec.gear_meshes = {stiff_gear, loose_gear, lossy_gear};
        spec.torques.push_back(TorqueSpec{"drive", 0, 0, {}, {}});
        CylinderSpec cylinder;
        cylinder.name = "cylinder";
        cylinder.node = 2;
        cylinder.phase = 1.0;
        spec.cylinders.push_back(cylinder);
        spec.order_torques.push_back(OrderTorqueSpec{"ripple", 1, 2.0, {}, {}});
        spec.spring_dampers.push_back(SpringDamperSpec{"coupling", 3, 0, {}, {}});
        spec.input_rates = {0};
        spec.speed_sources.push_back(SpeedSourceSpec{"prescribed", 3, 0, 1, {}, {}});
        spec.road_loads.push_back(RoadLoadSpec{"road", 1, {}, {}, {}, {}});
        MultistageSpringSpec damper;  // two stages on the positive side, one of its own on the negative
        damper.name = "damper";
        damper.a = 0;
        damper.b = 1;
        damper.stages = 2;
        damper.stages_negative = 1;
        spec.multistage_springs.push_back(damper);
        spec.position_controllers.push_back(PositionControllerSpec{"servo", 2, -1, {}, {}, {}});
        IdealGearSpec gearbox;  // ties n4 to n1 rigidly, lossy
        gearbox.name = "gearbox";
        gearbox.a = 1;
        gearbox.b = 4;
        gearbox.lossy = true;
        spec.ideal_gears.push_back(gearbox);

        for_each_element_kind([&](auto kind) {
            using Kind = decltype(kind);
            for (auto& e : ElementRow<Kind>::list(spec)) {
                std::map<std::string, int> seen;  // a list's fields (stages.k) repeat: each its own value
                Kind::for_each_field(
                    [&](const FieldInfo& info, Field& f) {
                        if (!info.in_use) return;
                        spec.parameter_names.push_back(e.name + "." + info.name);
                        p.push_back(typical_value(info.name) * (1.0 + 0.5 * seen[info.name]++));
                        f = Field::param(static_cast<int>(p.size() - 1));
                    },
                    e);
                if constexpr (Kind::outputs == ElementOutputs::none) continue;  // a constraint's torque
                OutputSpec torque;
                torque.name = e.name;
                torque.kind = OutputKind::torque;
                REQUIRE(spec.find_element(e.name, torque.element));
                spec.outputs.push_back(torque);
            }
        });

        std::vector<double> angle, values;
        for (int i = 0; i <= 720; ++i) {
            angle.push_back(-4.0 + 0.01 * i);
            values.push_back(1.0e5 + 3.0e6 * std::exp(-std::pow(angle.back() - 0.5, 2) * 4));
        }
        pressure = CrankAngleChannels(angle, {values});
    }
};

// A state with every element loaded: both clearances in contact, all speeds nonzero.
const std::vector<double> kState = {0.3, 0.05, -0.02, 0.1, 0.02, 10.0, -3.0, 7.0, 4.0, -1.2};  // n4 tied to n1
const double kInput[] = {5.0, 2.0};  // u and the slope of u

std::vector<double> derivative(const AllKindsNetwork& net, const std::vector<double>& p) {
    NetworkModel<double> model(net.spec);
    model.set_crank_angle_inputs(&net.pressure);
    model.set_parameters(p.data());
    std::vector<double> f(kState.size());
    model.derivative(kState.data(), kInput, f.data());
    return f;
}

}  // namespace

TEST_CASE("every element kind has one row of the table", "[model][elements]") {
    std::set<std::string> names;
    std::size_t position = 0;
    for_each_element_kind([&](auto kind) {
        using Row = ElementRow<decltype(kind)>;
        CHECK(static_cast<std::size_t>(Row::kind) == position++);  // ElementKind follows the table
        CHECK(std::string(element_kind_name(Row::kind)) == Row::name);
        names.insert(Row::name);
    });
    CHECK(position == kElementKindCount);
    CHECK(names == std::set<std::string>{"spring_damper", "clearance", "friction", "gear_mesh", "torque", "cylinder",
                                         "order_torque", "speed_source", "road_load",
                                         "multistage_spring", "position_controller", "ideal_gear"});
    // The test network below has elements of every kind.
    const AllKindsNetwork net;
    for (std::size_t count : element_counts(net.spec)) CHECK(count >= 1);
}

TEST_CASE("each kind's field walk visits each field once, in step over a spec and a bound element", "[model][elements]") {
    const std::map<std::string, std::vector<std::string>> expected = {
        {"spring_damper", {"k", "c"}},
        {"clearance", {"k_minus", "k_plus", "c_minus", "c_plus", "mu", "sigma"}},
        {"friction", {"c", "c_negative", "coulomb", "coulomb_negative", "breakaway", "stribeck_speed", "smoothing_speed"}},
        {"gear_mesh",
         {"ratio", "k", "c", "k_minus", "k_plus", "c_minus", "c_plus", "mu", "sigma", "efficiency", "smoothing_power"}},
        {"torque", {"offset", "scale", "value"}},
        {"cylinder", {"bore", "crank_radius", "rod_length", "mass", "p_atm"}},
        {"order_torque", {"amplitude", "phase"}},
        {"speed_source", {"speed", "scale"}},
        {"road_load", {"a", "b", "c", "smoothing_speed"}},
        {"multistage_spring",
         {"stages.angle", "stages.k", "stages_negative.angle", "stages_negative.k", "c", "smoothing_angle"}},
        {"position_controller", {"setpoint", "kp", "kd", "limits.min", "limits.max", "ki"}},
        {"ideal_gear", {"ratio", "efficiency", "smoothing_power"}}};
    for_each_element_kind([&](auto kind) {
        using Kind = decltype(kind);
        typename Kind::Spec spec{};
        typename Kind::template Bound<double> bound{};
        std::vector<std::string> visited;
        std::set<const void*> spec_fields, bound_fields;
        Kind::for_each_field(
            [&](const FieldInfo& info, Field& f, double& v) {
                visited.push_back(info.name);
                spec_fields.insert(&f);
                bound_fields.insert(&v);
                CHECK((info.sign == SignRule::any) == (info.role == nullptr));
            },
            spec, bound);
        INFO(ElementRow<Kind>::name);
        CHECK(visited == expected.at(ElementRow<Kind>::name));
        CHECK(spec_fields.size() == visited.size());  // each visit a different member
        CHECK(bound_fields.size() == visited.size());
    });
}

TEST_CASE("every field in use, bound to a parameter, moves the right-hand side", "[model][elements]") {
    const AllKindsNetwork net;
    const std::vector<double> f0 = derivative(net, net.p);
    for (std::size_t j = 0; j < net.p.size(); ++j) {
        const std::string& name = net.spec.parameter_names[j];
        INFO(name);
        std::vector<double> p = net.p;
        p[j] *= 1.01;
        const bool moved = derivative(net, p) != f0;
        // A gear mesh with backlash transmits the clearance law's torque: its k and c
        // only stand in for k_minus/k_plus and c_minus/c_plus in the experiment file.
        // The inertia of a node whose speed is prescribed acts only in the source's torque.
        if (name == "loose_gear.k" || name == "loose_gear.c" || name == "J_n3")
            CHECK_FALSE(moved);
        else
            CHECK(moved);
    }
}

TEST_CASE("an element's kept torque is the torque it transmits", "[model][elements]") {
    const AllKindsNetwork net;
    NetworkModel<double> model(net.spec);
    model.set_crank_angle_inputs(&net.pressure);
    model.set_parameters(net.p.data());
    std::vector<double> f(kState.size());
    model.derivative(kState.data(), kInput, f.data());
    for (std::size_t k = 0; k < net.spec.outputs.size(); ++k) {
        INFO(net.spec.outputs[k].name);
        CHECK(model.output_after_derivative(k, kState.data()) == model.output(k, kState.data(), kInput));
        CHECK(model.output(k, kState.data(), kInput) != 0.0);
    }
}

TEST_CASE("the torque formulas give the same bits for double, Dual and every lane of a pack", "[model][elements]") {
    constexpr int W = 4;
    const AllKindsNetwork net;
    const std::size_t m = net.p.size(), n = kState.size();
    // Lane l scales every parameter by its own factor.
    std::vector<std::vector<double>> lane_p(W, net.p);
    for (int l = 0; l < W; ++l)
        for (std::size_t j = 0; j < m; ++j) lane_p[l][j] *= 1.0 + 0.01 * l + 0.001 * static_cast<double>(j % 7);

    NetworkModel<Pack<W>> packed(net.spec);
    packed.set_crank_angle_inputs(&net.pressure);
    std::vector<Pack<W>> pp(m), xp(n), fp(n);
    for (std::size_t j = 0; j < m; ++j)
        for (int l = 0; l < W; ++l) pp[j].set(l, lane_p[l][j]);
    for (std::size_t i = 0; i < n; ++i) xp[i] = Pack<W>(kState[i]);
    packed.set_parameters(pp.data());
    packed.derivative(xp.data(), kInput, fp.data());

    for (int l = 0; l < W; ++l) {
        NetworkModel<double> model(net.spec);
        model.set_crank_angle_inputs(&net.pressure);
        model.set_parameters(lane_p[l].data());
        std::vector<double> f(n);
        model.derivative(kState.data(), kInput, f.data());
        NetworkModel<Dual> dual(net.spec);
        dual.set_crank_angle_inputs(&net.pressure);
        std::vector<Dual> pd(lane_p[l].begin(), lane_p[l].end()), xd(kState.begin(), kState.end()), fd(n);
        dual.set_parameters(pd.data());
        dual.derivative(xd.data(), kInput, fd.data());
        for (std::size_t i = 0; i < n; ++i) {
            INFO("lane " << l << ", state " << i);
            CHECK(fp[i][l] == f[i]);
            CHECK(fd[i].value() == f[i]);
        }
        for (std::size_t k = 0; k < net.spec.outputs.size(); ++k) {
            INFO("lane " << l << ", output " << net.spec.outputs[k].name);
            CHECK(packed.output_after_derivative(k, xp.data())[l] == model.output_after_derivative(k, kState.data()));
        }
    }
}

TEST_CASE("an order torque is A cos(k theta + phi) on its node and repeats every 1/k revolution", "[model][elements]") {
    // One node of J = 2 on a spring to ground (k = 10), an order-2 torque of A = 3, φ = 0.5.
    NetworkSpec spec;
    spec.preset = "custom";
    spec.parameter_names = {"A", "phi"};
    spec.input_names = {"u"};
    spec.nodes.push_back(NodeSpec{"shaft", Field::value(2.0), false});
    spec.spring_dampers.push_back(SpringDamperSpec{"mount", 0, kGround, Field::value(10.0), Field::value(0.0)});
    spec.order_torques.push_back(OrderTorqueSpec{"ripple", 0, 2.0, Field::param(0), Field::param(1)});
    OutputSpec ripple;
    ripple.name = "ripple";
    ripple.kind = OutputKind::torque;
    REQUIRE(spec.find_element("ripple", ripple.element));
    spec.outputs.push_back(ripple);

    NetworkModel<Dual> model(spec);
    const Dual p[2] = {Dual::variable(3.0, 0, 2), Dual::variable(0.5, 1, 2)};
    model.set_parameters(p);
    const double u[1] = {0.0};
    for (const double theta : {0.4, 0.4 + std::numbers::pi}) {  // half a revolution later: one period of order 2
        const Dual x[2] = {Dual(theta), Dual(1.5)};
        Dual f[2];
        model.derivative(x, u, f);
        const double torque = 3.0 * std::cos(2 * 0.4 + 0.5);
        CHECK(f[0].value() == Approx(1.5));
        CHECK(f[1].value() == Approx((torque - 10.0 * theta) / 2.0));
        CHECK(model.output(0, x, u).value() == Approx(torque));
        // d/dA = cos(kθ + φ), d/dφ = −A sin(kθ + φ).
        CHECK(model.output(0, x, u).derivative(0) == Approx(std::cos(2 * 0.4 + 0.5)));
        CHECK(model.output(0, x, u).derivative(1) == Approx(-3.0 * std::sin(2 * 0.4 + 0.5)));
    }
}

TEST_CASE("each kind declares its type name, keys, field units, channel and outputs", "[model][elements]") {
    std::set<std::string> types;
    for_each_element_kind([&](auto kind) {
        using Kind = decltype(kind);
        INFO(ElementRow<Kind>::name);
        CHECK(std::string(Kind::type_name) == ElementRow<Kind>::name);
        CHECK(types.insert(Kind::type_name).second);
        const std::set<std::string> keys(std::begin(Kind::keys), std::end(Kind::keys));
        CHECK(keys.size() == std::size(Kind::keys));  // no key twice
        CHECK(keys.count("type") == 0);
        CHECK(keys.count("name") == 0);
        typename Kind::Spec spec{};
        Kind::for_each_field(
            [&](const FieldInfo& info, Field&) {
                INFO(info.name);
                REQUIRE(info.unit != nullptr);
                CHECK(std::string(info.unit) != "");
                const std::string name = info.name;  // a key, or a list's key and the entry's (stages.k)
                CHECK(keys.count(name.substr(0, name.find('.'))) == 1);  // the reader may read it
                if (info.shorthand != nullptr) CHECK(keys.count(info.shorthand) == 1);
            },
            spec);
        if (Kind::channel.unit != nullptr) CHECK(std::string(Kind::channel.unit) != "");
        CHECK(element_has_output_side(ElementRow<Kind>::kind) ==
              (Kind::outputs == ElementOutputs::torque_each_side));
    });
    for_each_composite_kind([&](auto kind) {
        using Kind = decltype(kind);
        INFO(Kind::type_name);
        CHECK(types.insert(Kind::type_name).second);  // no composite hides a kind
    });
}

TEST_CASE("every element says how it enters a linearisation, in either mode", "[model][elements]") {
    const AllKindsNetwork net;
    std::vector<std::string> names;
    for (const NodeSpec& node : net.spec.nodes) names.push_back(node.name);
    for (const AngleDependence mode : {AngleDependence::revolution_mean, AngleDependence::operating_point}) {
        std::vector<double> added(net.spec.nodes.size(), 0.0);
        std::vector<char> prescribed(net.spec.nodes.size(), 0);
        const LinearisationPoint at{net.p, kState, mode, names, added, prescribed};
        NetworkSpec lin = net.spec;
        std::size_t notes = 0;
        for_each_element_kind([&](auto kind) {
            using Kind = decltype(kind);
            auto& replaced = ElementRow<Kind>::list(lin);
            for (std::size_t i = 0; i < replaced.size(); ++i) {
                const LinearNote note = Kind::linearise(ElementRow<Kind>::list(net.spec)[i], replaced[i], at);
                INFO(ElementRow<Kind>::name);
                CHECK(std::set<std::string>{"exact", "operating_point", "revolution_mean", "excitation", "prescribed"}
                          .count(note.method) == 1);
                CHECK(!note.note.empty());
                ++notes;
            }
        });
        std::size_t elements = 0;
        for (std::size_t count : element_counts(net.spec)) elements += count;
        CHECK(notes == elements);
        CHECK(prescribed == std::vector<char>{0, 0, 0, 1, 0});  // the speed source's node
        // The cylinder's reciprocating mass is averaged into its throw's inertia.
        CHECK((added[2] > 0) == (mode == AngleDependence::revolution_mean));
    }
}

TEST_CASE("the units of fields, inputs and outputs come from the tables", "[model][elements]") {
    AllKindsNetwork net;
    const std::vector<std::string> units = parameter_units(net.spec);
    const auto unit_of = [&](const std::string& name) {
        return units[static_cast<std::size_t>(net.spec.parameter_index(name))];
    };
    CHECK(unit_of("spring.k") == "N m/rad");
    CHECK(unit_of("bearing.c") == "N m s/rad");
    CHECK(unit_of("stop.mu") == "rad");
    CHECK(unit_of("stop.sigma") == "1/rad");
    CHECK(unit_of("stiff_gear.ratio") == "1");
    CHECK(unit_of("cylinder.bore") == "m");
    CHECK(unit_of("cylinder.p_atm") == "Pa");
    CHECK(unit_of("ripple.phase") == "rad");
    CHECK(unit_of("drive.offset") == "N m");
    CHECK(unit_of("J_n0") == "kg m^2");
    CHECK(input_unit(net.spec, 0) == "N m");  // the torque reads u (and so does the speed source)
    net.spec.torques.clear();
    CHECK(input_unit(net.spec, 0) == "rad/s");
    CHECK(input_unit(net.spec, 5).empty());

    std::size_t position = 0;
    std::set<std::string> keys;
    for_each_output_kind([&](auto kind) {
        using Kind = decltype(kind);
        CHECK(static_cast<std::size_t>(OutputRow<Kind>::kind) == position++);
        CHECK(std::string(output_kind_key(OutputRow<Kind>::kind)) == Kind::key);
        CHECK(std::string(output_kind_unit(OutputRow<Kind>::kind)) == Kind::unit);
        keys.insert(Kind::key);
    });
    CHECK(keys == std::set<std::string>{"speed", "angle", "torque"});
}

TEST_CASE("a kind reads its entry and the table checks its fields' signs", "[model][elements]") {
    NetworkSpec net = two_nodes();
    TextSource mesh({{"between", ""}, {"ratio", "3"}, {"k", "1000"}, {"c", "p"}});
    read_element<elements::GearMesh>(mesh, "stage", net);
    REQUIRE(net.gear_meshes.size() == 1);
    CHECK(net.gear_meshes[0].ratio.constant == 3.0);
    CHECK(net.gear_meshes[0].c.parameter == 0);
    CHECK_FALSE(net.gear_meshes[0].has_clearance);

    const auto gear = [](TextSource& s, NetworkSpec& n) { read_element<elements::GearMesh>(s, "stage", n); };
    CHECK(read_error(TextSource({{"between", ""}, {"ratio", "0"}, {"k", "1000"}}), gear) ==
          "ratio: must not be zero: a gear ratio (got 0)");
    CHECK(read_error(TextSource({{"between", ""}, {"ratio", "2"}, {"k", "-1"}}), gear) ==
          "k: cannot be negative: a mesh stiffness (got -1)");
    // A clearance law's k stands for k_minus and k_plus: the error names the key given.
    const auto clearance = [](TextSource& s, NetworkSpec& n) { read_element<elements::Clearance>(s, "stop", n); };
    CHECK(read_error(TextSource({{"between", ""}, {"k", "-5"}, {"mu", "0.01"}}), clearance) ==
          "k: cannot be negative: a contact stiffness (got -5)");
    // A kind's own rule against the others of its kind: one speed source per node.
    const auto two_sources = [](TextSource& s, NetworkSpec& n) {
        read_element<elements::SpeedSource>(s, "first", n);
        read_element<elements::SpeedSource>(s, "second", n);
    };
    CHECK(read_error(TextSource({{"node", "b"}, {"speed", "10"}}), two_sources) ==
          "node: node 'b' already has its speed prescribed by 'first'");
    // A composite adds its parts: a reference node, a speed source and a spring-damper.
    TextSource controller({{"node", "a"}, {"setpoint", "12"}, {"kp", "2"}, {"ki", "p"}});
    elements::SpeedController::build(controller, "pi", net);
    CHECK(net.nodes.back().name == "pi.reference");
    REQUIRE(net.speed_sources.size() == 1);
    CHECK(net.speed_sources[0].speed.constant == 12.0);
    REQUIRE(net.spring_dampers.size() == 1);
    CHECK(net.spring_dampers[0].k.parameter == 0);  // k = ki
    CHECK(net.spring_dampers[0].c.constant == 2.0);  // c = kp
}

}  // namespace TVID_UNITY_ID

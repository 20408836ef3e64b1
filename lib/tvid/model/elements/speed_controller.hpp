#pragma once
// A PI speed controller: T = kp·(ω_set − ω) + ki·∫(ω_set − ω) dt on a node. It adds no
// kind: its integral is the twist of a spring (k = ki, c = kp) from a reference node that
// turns at the setpoint. The reader builds it from the node NAME.reference, the speed
// source NAME.setpoint that drives it, and the spring-damper NAME joining it to `node`,
// whose torque is the controller's.
//
// With `sample_period` it is digital (a drive's speed loop): the sampled controller of
// position_controller.hpp measuring speed, kp on the speed error (the backward difference
// of its sampled angles), ki on its integral, with `delay`, `limits` and `angle_average`.

#include <string>

#include "tvid/model/element_reading.hpp"
#include "tvid/model/element_source.hpp"
#include "tvid/model/elements/position_controller.hpp"
#include "tvid/model/network_spec.hpp"
#include "tvid/util/text.hpp"

namespace tvid::elements {

struct SpeedController {
    // ---- the experiment file: `{ type: speed_controller, node: NODE, setpoint: CHANNEL | RAD_PER_S, kp: KP, ki: KI }`
    static constexpr const char* type_name = "speed_controller";
    static constexpr const char* summary = "a PI speed controller on a node: T = kp*(w_set - w) + ki*integral(w_set - w)";
    static constexpr const char* keys[] = {"node", "setpoint", "kp", "ki", "limits", "sample_period", "delay",
                                           "angle_average"};
    /// Its numbers, as `tvid models` lists them (the spring-damper it builds holds kp as c, ki as k).
    static constexpr FieldInfo fields[] = {
        {"setpoint", nullptr, SignRule::any, "rad/s"},
        {"kp", "a controller gain", SignRule::non_negative, "N m s/rad"},
        {"ki", "a controller gain", SignRule::non_negative, "N m/rad"},
        {"limits.min", nullptr, SignRule::any, "N m"},
        {"limits.max", nullptr, SignRule::any, "N m"},
    };

    static void build(ElementSource& src, const std::string& name, NetworkSpec& net) {
        if (src.has("sample_period")) return build_sampled(src, name, net);
        for (const char* key : {"limits", "delay", "angle_average"})
            if (src.has(key))
                src.fail(key, "belongs to a sampled speed controller: give its sample_period (a continuous one is a "
                              "spring and damper from a reference node, which nothing limits or delays)");
        const int drive = src.node("node");
        NodeSpec reference;
        reference.name = name + ".reference";
        reference.inertia = Field::value(1.0);  // prescribed motion: its inertia only scales its reaction
        if (net.node_index(reference.name) >= 0) src.fail("name", "a node named '" + reference.name + "' already exists");
        for (const char* key : {"kp", "ki"}) {
            const Field f = src.field(key);
            if (!f.is_parameter() && !(f.constant >= 0))
                src.fail(key, "cannot be negative: a controller gain (got " + number_text(f.constant) + ")");
        }
        SpeedSourceSpec setpoint;
        setpoint.name = name + ".setpoint";
        if (!src.claim_name(setpoint.name)) src.fail("name", "an element named '" + setpoint.name + "' already exists");
        setpoint.node = static_cast<int>(net.nodes.size());
        if (!src.has("setpoint"))
            src.fail_missing("setpoint", "(a speed channel, a constant speed in rad/s or a parameter)");
        const bool constant = src.names_constant("setpoint");
        net.nodes.push_back(reference);
        if (constant)
            setpoint.speed = src.field("setpoint");
        else
            setpoint.input = src.time_input("setpoint", "a speed");
        add_element<SpeedSource>(src, net, setpoint);
        add_element<SpringDamper>(src, net, SpringDamperSpec{name, setpoint.node, drive, src.field("ki"), src.field("kp")});
    }

    // A digital speed loop: one sampled controller element NAME measuring speed.
    static void build_sampled(ElementSource& src, const std::string& name, NetworkSpec& net) {
        PositionControllerSpec e = spec_at_ends<PositionController>(src, name);
        e.measures = ControlledQuantity::speed;
        PositionController::read_setpoint(src, e, "a speed", "(a speed channel, a constant speed in rad/s or a parameter)");
        e.kp = src.field("kp");
        e.ki = src.field("ki");
        PositionController::read_sampling(src, e);
        PositionController::read_limits(src, e);
        check_field_signs<PositionController>(src, e);
        PositionController::check(e, ConstantFieldBounds(src));
        add_element<PositionController>(src, net, e);
    }
};

}  // namespace tvid::elements

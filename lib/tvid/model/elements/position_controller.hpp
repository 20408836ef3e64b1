#pragma once
// A PD position controller on a node, as a drive's position loop: proportional on the
// angle error, derivative on the measured speed (not on the error, so a setpoint step
// gives no derivative kick).

#include <algorithm>
#include <string>

#include "tvid/model/element_source.hpp"
#include "tvid/model/element_traits.hpp"
#include "tvid/model/elements/node_motion.hpp"
#include "tvid/model/field.hpp"

namespace tvid {

/// T = kp·(θ_set − θa) − kd·ωa on node a, θ_set a measured angle channel (input ≥ 0) or a
/// constant (a number or a parameter); with `limits: [min, max]` the command saturates there
/// (an actuator's torque limit).
struct PositionControllerSpec {
    std::string name;
    int node = 0;
    int input = -1;  ///< index into NetworkSpec::input_names; −1: the constant `setpoint`
    Field setpoint = Field::value(0.0), kp = Field::value(0.0), kd = Field::value(0.0);
    bool limited = false;
    Field lower = Field::value(0.0), upper = Field::value(0.0);  ///< the torque limits [N m], when limited
};

namespace elements {

struct PositionController {
    using Spec = PositionControllerSpec;
    template <class T>
    struct Bound {
        int node = 0, input = -1;
        T setpoint, kp, kd, lower, upper;
        bool limited = false;
    };

    // ---- the experiment file: `{ type: position_controller, node: NODE, setpoint: CHANNEL | RAD, kp: KP, kd: KD,
    //      limits: [MIN, MAX] }`
    static constexpr const char* type_name = "position_controller";
    static constexpr const char* summary =
        "a PD position controller on a node: T = kp*(theta_set - theta) - kd*omega (derivative on the measured speed)";
    static constexpr const char* keys[] = {"node", "setpoint", "kp", "ki", "kd", "limits"};

    static Spec read(ElementSource& src, const std::string& name) {
        Spec e;
        e.name = name;
        e.node = src.node("node");
        if (!src.has("setpoint"))
            src.fail_missing("setpoint", "(an angle channel [rad], a constant angle or a parameter)");
        if (src.names_constant("setpoint"))
            e.setpoint = src.field("setpoint");
        else
            e.input = src.time_input("setpoint", "an angle");
        e.kp = src.field("kp");
        e.kd = src.field_or("kd", Field::value(0.0));
        // An integral of the angle error is a state of its own, which the network's states
        // (each node's angle and speed) do not hold.
        if (src.has("ki") && (src.field("ki").is_parameter() || src.field("ki").constant != 0))
            src.fail("ki", "a continuous position controller is PD: the integral of the angle error needs a state "
                           "the network does not carry; leave ki out, or close the drive's speed loop with a "
                           "speed_controller (PI)");
        if (src.has("limits")) {
            const auto limits = src.field_pair("limits");
            e.limited = true;
            e.lower = limits.first;
            e.upper = limits.second;
        }
        return e;
    }

    /// After the sign rules: the limits hold zero between them (a constant pair).
    static void check(const Spec& e, const ElementSource& src) {
        if (!e.limited || e.lower.is_parameter() || e.upper.is_parameter()) return;
        if (!(e.lower.constant <= 0.0 && 0.0 <= e.upper.constant && e.lower.constant < e.upper.constant))
            src.fail("limits", "expected [min, max] with min <= 0 <= max and min < max, got [" +
                                   linear_number(e.lower.constant) + ", " + linear_number(e.upper.constant) + "]");
    }

    /// f(info, field...) for each numeric field, of each of s, e... (a spec first, then bound elements) in step.
    template <class F, class Spec_, class... E>
    static void for_each_field(F&& f, Spec_& s, E&... e) {
        f(FieldInfo{"setpoint", nullptr, SignRule::any, "rad", s.input < 0}, s.setpoint, e.setpoint...);
        f(FieldInfo{"kp", "a controller gain", SignRule::non_negative, "N m/rad"}, s.kp, e.kp...);
        f(FieldInfo{"kd", "a controller gain", SignRule::non_negative, "N m s/rad"}, s.kd, e.kd...);
        f(FieldInfo{"limits.min", nullptr, SignRule::any, "N m", s.limited}, s.lower, e.lower...);
        f(FieldInfo{"limits.max", nullptr, SignRule::any, "N m", s.limited}, s.upper, e.upper...);
    }

    static constexpr ChannelUse channel{"rad"};  ///< a measured angle setpoint, by time
    static int channel_of(const Spec& s) { return s.input; }
    static constexpr ElementOutputs outputs = ElementOutputs::torque;

    /// Linear: kp a spring and kd a damper from the node to ground, the setpoint an input (at
    /// the operating point's command, inside its limits or saturated there).
    static LinearNote linearise(const Spec& s, Spec&, const LinearisationPoint&) {
        if (s.limited) return {"operating_point", "kp a spring and kd a damper to ground while inside its limits; "
                                                  "saturated, a constant torque"};
        return {"exact", "linear: kp a spring and kd a damper to ground, the setpoint an input"};
    }

    // ---- the equations of motion

    template <class T>
    static void bind(const Spec& s, Bound<T>& e) {
        e.node = s.node;
        e.input = s.input;
        e.limited = s.limited;
    }

    static constexpr bool acts_at_rest = true;  ///< it holds its node at the setpoint

    /// The controller's torque on its node.
    template <class T>
    [[gnu::always_inline]] static T torque(const Bound<T>& e, const NodeMotion<T>& m) {
        using std::max;
        using std::min;
        const T target = e.input < 0 ? e.setpoint : T(m.u[e.input]);
        const T command = e.kp * (target - m.theta[e.node]) - e.kd * m.twist_rate(e.node, kGround);
        return e.limited ? min(max(command, e.lower), e.upper) : command;
    }

    template <class T>
    [[gnu::always_inline]] static void load(const Bound<T>& e, const T& t, const NodeMotion<T>&, T* node_torque) {
        node_torque[e.node] += t;
    }
};

}  // namespace elements
}  // namespace tvid

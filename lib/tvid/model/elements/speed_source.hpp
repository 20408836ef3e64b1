#pragma once
// A prescribed speed: a node turns at a measured speed (or a constant one), whatever
// torque that takes, as a speed-controlled drive holds its shaft. The node's angle is the
// integral of that speed; the elements joined to it see the prescribed speed; its state
// speed follows the channel's slope. The source's torque (its reaction) is what it must
// apply for that motion: J·ω̇ minus every other torque on the node.

#include <string>

#include "tvid/model/elements/node_motion.hpp"
#include "tvid/model/field.hpp"

namespace tvid {

/// ω_node(t) = scale · u(t) (a measured speed channel) or `speed` (a constant).
struct SpeedSourceSpec {
    std::string name;
    int node = 0;
    int input = -1;  ///< the speed channel, an index into NetworkSpec::input_names; -1: a constant speed
    int rate = -1;   ///< where the channel's time derivative is among the inputs (NetworkSpec::input_rates)
    Field speed = Field::value(0.0);  ///< the constant speed [rad/s], when input is -1
    Field scale = Field::value(1.0);  ///< the channel's factor, when input is a channel
};

namespace elements {

struct SpeedSource {
    using Spec = SpeedSourceSpec;
    template <class T>
    struct Bound {
        int node = 0, input = -1, rate = -1;
        T speed, scale;
    };

    /// f(info, field...) for each numeric field, of each of s, e... (a spec first, then bound elements) in step.
    template <class F, class Spec_, class... E>
    static void for_each_field(F&& f, Spec_& s, E&... e) {
        f(FieldInfo{"speed", nullptr, SignRule::any, s.input < 0}, s.speed, e.speed...);
        f(FieldInfo{"scale", nullptr, SignRule::any, s.input >= 0}, s.scale, e.scale...);
    }

    template <class T>
    static void bind(const Spec& s, Bound<T>& e) {
        e.node = s.node;
        e.input = s.input;
        e.rate = s.rate;
    }

    static constexpr bool acts_at_rest = true;

    /// Nothing while the torques are summed: the reaction is set afterwards, from the
    /// node's other torques (NetworkModel::impose_prescribed_motion).
    template <class T>
    [[gnu::always_inline]] static T torque(const Bound<T>&, const NodeMotion<T>&) {
        return T(0);
    }

    template <class T>
    [[gnu::always_inline]] static void load(const Bound<T>&, const T&, const NodeMotion<T>&, T*) {}

    /// The node's speed at the inputs u.
    template <class T>
    [[gnu::always_inline]] static T prescribed_speed(const Bound<T>& e, const double* u) {
        return e.input < 0 ? e.speed : e.scale * u[e.input];
    }

    /// Its time derivative: the channel's slope (zero for a constant speed).
    template <class T>
    [[gnu::always_inline]] static T prescribed_acceleration(const Bound<T>& e, const double* u) {
        return e.input < 0 ? T(0) : e.scale * u[e.rate];
    }
};

}  // namespace elements
}  // namespace tvid

#pragma once
// A prescribed speed: a node turns at a measured speed (or a constant one), whatever
// torque that takes, as a speed-controlled drive holds its shaft. The node's angle is the
// integral of that speed; the elements joined to it see the prescribed speed; its state
// speed follows the channel's slope. The source's torque (its reaction) is what it must
// apply for that motion: J·ω̇ minus every other torque on the node.

#include <algorithm>
#include <cstddef>
#include <string>
#include <vector>

#include "tvid/model/element_source.hpp"
#include "tvid/model/element_traits.hpp"
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
    struct Bound : OnOneNode {
        int input = -1, rate = -1;
        T speed, scale;
    };

    // ---- the experiment file: `{ type: speed_source, node: NODE, input: CHANNEL, scale: S }` or
    // `{ type: speed_source, node: NODE, speed: RAD_PER_S }`
    static constexpr const char* type_name = "speed_source";
    static constexpr const char* summary = "a node held at a measured or constant speed, whatever torque that takes";
    static constexpr const char* keys[] = {"node", "input", "speed", "scale"};

    static Spec read(ElementSource& src, const std::string& name) {
        Spec e = spec_at_ends<SpeedSource>(src, name);
        if (src.has("input") == src.has("speed"))
            src.fail(src.has("input") ? "speed" : "input",
                     "give either input (a measured speed channel) or speed (a constant, rad/s), not both");
        if (src.has("input")) {
            e.input = src.time_input("input", "a speed");
            e.scale = src.field_or("scale", Field::value(1.0));
        } else {
            if (src.has("scale")) src.fail("scale", "scale applies to a speed channel (input), not a constant speed");
            e.speed = src.field("speed");
        }
        return e;
    }

    /// A node's speed is prescribed once.
    static void check_against(const Spec& e, const std::vector<Spec>& others, const ElementSource& src) {
        for (const Spec& other : others)
            if (other.node == e.node)
                src.fail("node", "node '" + src.node_name(e.node) + "' already has its speed prescribed by '" +
                                     other.name + "'");
    }

    /// Once every element is read: a speed channel's slope follows the inputs (input_count
    /// of them), one per channel, in NetworkSpec::input_rates.
    static void finish_reading(std::vector<Spec>& sources, std::vector<int>& input_rates, std::size_t input_count) {
        for (Spec& e : sources) {
            if (e.input < 0) continue;
            auto it = std::find(input_rates.begin(), input_rates.end(), e.input);
            if (it == input_rates.end()) it = input_rates.insert(it, e.input);
            e.rate = static_cast<int>(input_count) + static_cast<int>(it - input_rates.begin());
        }
    }

    /// f(info, field...) for each numeric field, of each of s, e... (a spec first, then bound elements) in step.
    template <class F, class Spec_, class... E>
    static void for_each_field(F&& f, Spec_& s, E&... e) {
        f(FieldInfo{"speed", nullptr, SignRule::any, "rad/s", s.input < 0}, s.speed, e.speed...);
        f(FieldInfo{"scale", nullptr, SignRule::any, "1", s.input >= 0}, s.scale, e.scale...);
    }

    static constexpr ChannelUse channel{"rad/s"};  ///< a measured speed, by time
    static int channel_of(const Spec& s) { return s.input; }
    static constexpr ElementOutputs outputs = ElementOutputs::torque;  ///< its reaction

    /// Its node is held to the input: that node keeps its angle state but no speed state.
    static LinearNote linearise(const Spec& e, Spec&, const LinearisationPoint& at) {
        at.prescribed[static_cast<std::size_t>(e.node)] = 1;
        return {"prescribed", "prescribes the speed of " + at.node_name(e.node) +
                                  ": that node is held to the input (no speed state), its angle follows it"};
    }

    // ---- the equations of motion

    template <class T>
    static void bind(const Spec& s, Bound<T>& e) {
        e.input = s.input;
        e.rate = s.rate;
    }

    static constexpr bool acts_at_rest = true;
    static constexpr ElementEnds ends = ElementEnds::one_node;

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

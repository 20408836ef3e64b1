#pragma once
// An external torque on a node: from a measured input channel, or a constant load (a number
// or a parameter: a drag or a brake whose torque is known or to be identified).

#include <string>

#include "tvid/model/element_source.hpp"
#include "tvid/model/element_traits.hpp"
#include "tvid/model/elements/node_motion.hpp"
#include "tvid/model/field.hpp"

namespace tvid {

/// External torque on a node from a measured input channel:
/// T = scale · (u(t) − offset); `offset` is the sensor's amplitude shift (Yoshida & Takamatsu eq. 14).
/// Or a constant torque T = value (input −1), e.g. a load a brake holds.
struct TorqueSpec {
    std::string name;
    int node = 0;
    int input = 0;  ///< index into NetworkSpec::input_names; −1: the constant `value`
    Field offset = Field::value(0.0);
    Field scale = Field::value(1.0);
    Field value = Field::value(0.0);  ///< the constant torque [N m] when input is −1
};

namespace elements {

struct Torque {
    using Spec = TorqueSpec;
    template <class T>
    struct Bound : OnOneNode {
        int input = 0;
        T offset, scale, value;
    };

    // ---- the experiment file: `{ type: torque, node: NODE, input: CHANNEL, offset: O, scale: S }`
    //      or a constant torque `{ type: torque, node: NODE, value: T }` (a number or a parameter)
    static constexpr const char* type_name = "torque";
    static constexpr const char* summary =
        "an external torque on a node: from a measured input channel, or a constant value (a number or a parameter)";
    static constexpr const char* keys[] = {"node", "input", "offset", "scale", "value"};

    static Spec read(ElementSource& src, const std::string& name) {
        Spec e = spec_at_ends<Torque>(src, name);
        if (src.has("value")) {
            for (const char* key : {"input", "offset", "scale"})
                if (src.has(key))
                    src.fail(key, "a torque is either a constant value: or a measured input:, not both");
            e.input = -1;
            e.value = src.field("value");
            return e;
        }
        if (!src.has("input"))
            src.fail_missing("input", "(a measured torque channel, or value: a constant torque in N m or a parameter)");
        e.input = src.time_input("input", "a torque");
        e.offset = src.field_or("offset", Field::value(0.0));
        e.scale = src.field_or("scale", Field::value(1.0));
        return e;
    }

    /// f(info, field...) for each numeric field, of each of e... (a spec first, then bound elements) in step.
    /// A constant torque leaves offset and scale unused, a measured one its value.
    template <class F, class Spec_, class... E>
    static void for_each_field(F&& f, Spec_& s, E&... e) {
        const bool constant = s.input < 0;
        f(FieldInfo{"offset", nullptr, SignRule::any, "N m", !constant}, s.offset, e.offset...);
        f(FieldInfo{"scale", nullptr, SignRule::any, "1", !constant}, s.scale, e.scale...);
        f(FieldInfo{"value", nullptr, SignRule::any, "N m", constant}, s.value, e.value...);
    }

    static constexpr ChannelUse channel{"N m"};  ///< a measured torque, by time
    static int channel_of(const Spec& s) { return s.input; }
    static constexpr ElementOutputs outputs = ElementOutputs::torque;

    /// Affine in its input: the input's column of B; a constant torque moves only the
    /// operating point.
    static LinearNote linearise(const Spec& s, Spec&, const LinearisationPoint&) {
        return s.input < 0 ? LinearNote{"exact", "a constant torque: no column of A or B"}
                           : LinearNote{"exact", "an input: B's column"};
    }

    // ---- the equations of motion

    template <class T>
    static void bind(const Spec& s, Bound<T>& e) {
        e.input = s.input;
    }

    static constexpr bool acts_at_rest = true;
    static constexpr ElementEnds ends = ElementEnds::one_node;

    /// The applied torque scale·(u − offset), or the constant value.
    template <class T>
    [[gnu::always_inline]] static T torque(const Bound<T>& e, const NodeMotion<T>& m) {
        if (e.input < 0) return e.value;
        return e.scale * (m.u[e.input] - e.offset);
    }

    template <class T>
    [[gnu::always_inline]] static void load(const Bound<T>& e, const T& t, const NodeMotion<T>&, T* node_torque) {
        node_torque[e.node] += t;
    }
};

}  // namespace elements
}  // namespace tvid

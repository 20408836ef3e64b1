#pragma once
// An external torque on a node from a measured input channel.

#include <string>

#include "tvid/model/element_source.hpp"
#include "tvid/model/element_traits.hpp"
#include "tvid/model/elements/node_motion.hpp"
#include "tvid/model/field.hpp"

namespace tvid {

/// External torque on a node from a measured input channel:
/// T = scale · (u(t) − offset); `offset` is the sensor's amplitude shift (Yoshida & Takamatsu eq. 14).
struct TorqueSpec {
    std::string name;
    int node = 0;
    int input = 0;  ///< index into NetworkSpec::input_names
    Field offset = Field::value(0.0);
    Field scale = Field::value(1.0);
};

namespace elements {

struct Torque {
    using Spec = TorqueSpec;
    template <class T>
    struct Bound {
        int node = 0, input = 0;
        T offset, scale;
    };

    // ---- the experiment file: `{ type: torque, node: NODE, input: CHANNEL, offset: O, scale: S }`
    static constexpr const char* type_name = "torque";
    static constexpr const char* summary = "an external torque on a node from a measured input channel";
    static constexpr const char* keys[] = {"node", "input", "offset", "scale"};

    static Spec read(ElementSource& src, const std::string& name) {
        Spec e;
        e.name = name;
        e.node = src.node("node");
        e.input = src.time_input("input", "a torque");
        e.offset = src.field_or("offset", Field::value(0.0));
        e.scale = src.field_or("scale", Field::value(1.0));
        return e;
    }

    /// f(info, field...) for each numeric field, of each of e... (a spec first, then bound elements) in step.
    template <class F, class... E>
    static void for_each_field(F&& f, E&... e) {
        f(FieldInfo{"offset", nullptr, SignRule::any, "N m"}, e.offset...);
        f(FieldInfo{"scale", nullptr, SignRule::any, "1"}, e.scale...);
    }

    static constexpr ChannelUse channel{"N m"};  ///< a measured torque, by time
    static int channel_of(const Spec& s) { return s.input; }
    static constexpr ElementOutputs outputs = ElementOutputs::torque;

    /// Affine in its input: the input's column of B.
    static LinearNote linearise(const Spec&, Spec&, const LinearisationPoint&) { return {"exact", "an input: B's column"}; }

    // ---- the equations of motion

    template <class T>
    static void bind(const Spec& s, Bound<T>& e) {
        e.node = s.node;
        e.input = s.input;
    }

    static constexpr bool acts_at_rest = true;

    /// The applied torque scale·(u − offset).
    template <class T>
    [[gnu::always_inline]] static T torque(const Bound<T>& e, const NodeMotion<T>& m) {
        return e.scale * (m.u[e.input] - e.offset);
    }

    template <class T>
    [[gnu::always_inline]] static void load(const Bound<T>& e, const T& t, const NodeMotion<T>&, T* node_torque) {
        node_torque[e.node] += t;
    }
};

}  // namespace elements
}  // namespace tvid

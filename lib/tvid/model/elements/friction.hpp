#pragma once
// Viscous friction of a node to ground.

#include <string>

#include "tvid/model/element_source.hpp"
#include "tvid/model/element_traits.hpp"
#include "tvid/model/elements/node_motion.hpp"
#include "tvid/model/field.hpp"

namespace tvid {

/// Viscous friction to ground on one node: torque −c·ω.
struct FrictionSpec {
    std::string name;
    int node = 0;
    Field c;
};

namespace elements {

struct Friction {
    using Spec = FrictionSpec;
    template <class T>
    struct Bound {
        int node = 0;
        T c;
    };

    // ---- the experiment file: `{ type: friction, node: NODE, c: C }`
    static constexpr const char* type_name = "friction";
    static constexpr const char* summary = "viscous friction of a node to ground: T = -c*omega";
    static constexpr const char* keys[] = {"node", "c"};

    static Spec read(ElementSource& src, const std::string& name) {
        const int node = src.node("node");
        return Spec{name, node, src.field("c")};
    }

    /// f(info, field...) for each numeric field, of each of e... (a spec first, then bound elements) in step.
    template <class F, class... E>
    static void for_each_field(F&& f, E&... e) {
        f(FieldInfo{"c", "a friction coefficient", SignRule::non_negative, "N m s/rad"}, e.c...);
    }

    static constexpr ChannelUse channel{};  ///< reads no channel
    static int channel_of(const Spec&) { return -1; }
    static constexpr ElementOutputs outputs = ElementOutputs::torque;

    /// Linear in ω: it enters as it is.
    static LinearNote linearise(const Spec&, Spec&, const LinearisationPoint&) { return {"exact", "linear"}; }

    // ---- the equations of motion

    template <class T>
    static void bind(const Spec& s, Bound<T>& e) {
        e.node = s.node;
    }

    static constexpr bool acts_at_rest = false;  ///< no torque at zero speed

    /// The friction torque c·ω.
    template <class T>
    [[gnu::always_inline]] static T torque(const Bound<T>& e, const NodeMotion<T>& m) {
        return e.c * m.omega[e.node];
    }

    template <class T>
    [[gnu::always_inline]] static void load(const Bound<T>& e, const T& t, const NodeMotion<T>&, T* node_torque) {
        node_torque[e.node] -= t;
    }
};

}  // namespace elements
}  // namespace tvid

#pragma once
// The linear spring and viscous damper between two nodes, or a node and ground.

#include <string>

#include "tvid/model/element_source.hpp"
#include "tvid/model/element_traits.hpp"
#include "tvid/model/elements/node_motion.hpp"
#include "tvid/model/elements/two_node_load.hpp"
#include "tvid/model/field.hpp"

namespace tvid {

/// Linear spring and viscous damper between node a and node b (or ground, b = kGround).
/// Torque on a: −k(θa − θb) − c(ωa − ωb); the opposite on b.
struct SpringDamperSpec {
    std::string name;
    int a = 0, b = kGround;
    Field k, c;
};

namespace elements {

struct SpringDamper : TwoNodeLoad {  // its load: −t on a, +t on b
    using Spec = SpringDamperSpec;
    template <class T>
    struct Bound : BetweenTwoNodes {
        T k, c;
    };

    // ---- the experiment file: `{ type: spring_damper, between: [a, b], k: K, c: C }`
    static constexpr const char* type_name = "spring_damper";
    static constexpr const char* summary = "a linear spring and viscous damper between two nodes, or a node and ground";
    static constexpr const char* keys[] = {"between", "k", "c"};

    static Spec read(ElementSource& src, const std::string& name) {
        Spec e = spec_at_ends<SpringDamper>(src, name);
        e.k = src.field("k");
        e.c = src.field_or("c", Field::value(0.0));
        return e;
    }

    /// f(info, field...) for each numeric field, of each of e... (a spec first, then bound elements) in step.
    template <class F, class... E>
    static void for_each_field(F&& f, E&... e) {
        f(FieldInfo{"k", "a stiffness", SignRule::non_negative, "N m/rad"}, e.k...);
        f(FieldInfo{"c", "a damping coefficient", SignRule::non_negative, "N m s/rad"}, e.c...);
    }

    static constexpr ChannelUse channel{};  ///< reads no channel
    static int channel_of(const Spec&) { return -1; }
    static constexpr ElementOutputs outputs = ElementOutputs::torque;

    /// Linear already: it enters the linearisation as it is.
    static LinearNote linearise(const Spec&, Spec&, const LinearisationPoint&) { return {"exact", "linear"}; }

    // ---- the equations of motion (its fields and nodes are all its binding needs)

    static constexpr bool acts_at_rest = true;
    static constexpr ElementEnds ends = ElementEnds::two_nodes;

    /// The torque transmitted from a to b.
    template <class T>
    [[gnu::always_inline]] static T torque(const Bound<T>& e, const NodeMotion<T>& m) {
        return e.k * m.twist(e.a, e.b) + e.c * m.twist_rate(e.a, e.b);
    }
};

}  // namespace elements
}  // namespace tvid

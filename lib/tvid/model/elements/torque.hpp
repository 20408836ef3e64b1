#pragma once
// An external torque on a node from a measured input channel.

#include <string>

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

    /// f(info, field...) for each numeric field, of each of e... (a spec first, then bound elements) in step.
    template <class F, class... E>
    static void for_each_field(F&& f, E&... e) {
        f(FieldInfo{"offset"}, e.offset...);
        f(FieldInfo{"scale"}, e.scale...);
    }

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

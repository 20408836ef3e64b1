#pragma once
// A torque synchronous with a node's rotation: one order of a once- (or k-times-) per-
// revolution disturbance of a motor, a shaft's misalignment or a gear's runout.

#include <string>

// math::sincos of each scalar type the right-hand side runs on: double and Pack, Dual, PackedDual.
#include "tvid/model/dual.hpp"
#include "tvid/model/elements/node_motion.hpp"
#include "tvid/model/field.hpp"
#include "tvid/model/packed_dual.hpp"
#include "tvid/simd/elementary_functions.hpp"

namespace tvid {

/// Torque A·cos(k·θ + φ) on a node, with θ the node's own angle: order k (1 = once per
/// revolution of that node, 0.5 = once per two), amplitude A [N m], phase φ [rad]
/// against the node's angle zero. Several orders are several elements.
struct OrderTorqueSpec {
    std::string name;
    int node = 0;
    double order = 1.0;
    Field amplitude, phase;
};

namespace elements {

struct OrderTorque {
    using Spec = OrderTorqueSpec;
    template <class T>
    struct Bound {
        int node = 0;
        double order = 1.0;
        T amplitude, phase;
    };

    /// f(info, field...) for each numeric field, of each of e... (a spec first, then bound elements) in step.
    template <class F, class... E>
    static void for_each_field(F&& f, E&... e) {
        f(FieldInfo{"amplitude"}, e.amplitude...);
        f(FieldInfo{"phase"}, e.phase...);
    }

    template <class T>
    static void bind(const Spec& s, Bound<T>& e) {
        e.node = s.node;
        e.order = s.order;
    }

    static constexpr bool acts_at_rest = true;  ///< a function of the angle alone

    /// A·cos(k·θ + φ).
    template <class T>
    [[gnu::always_inline]] static T torque(const Bound<T>& e, const NodeMotion<T>& m) {
        T sin_angle, cos_angle;
        math::sincos(T(e.order) * m.theta[e.node] + e.phase, sin_angle, cos_angle);
        return e.amplitude * cos_angle;
    }

    template <class T>
    [[gnu::always_inline]] static void load(const Bound<T>& e, const T& t, const NodeMotion<T>&, T* node_torque) {
        node_torque[e.node] += t;
    }
};

}  // namespace elements
}  // namespace tvid

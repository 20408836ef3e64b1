#pragma once
// A torque synchronous with a node's rotation: one order of a once- (or k-times-) per-
// revolution disturbance of a motor, a shaft's misalignment or a gear's runout.

#include <string>

// math::sincos of each scalar type the right-hand side runs on: double and Pack, Dual, PackedDual.
#include "tvid/model/dual.hpp"
#include "tvid/model/element_source.hpp"
#include "tvid/model/element_traits.hpp"
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
    struct Bound : OnOneNode {
        double order = 1.0;
        T amplitude, phase;
    };

    // ---- the experiment file: `{ type: order_torque, node: NODE, order: K, amplitude: A, phase: PHI }`
    static constexpr const char* type_name = "order_torque";
    static constexpr const char* summary = "a torque synchronous with a node's rotation: one order of a per-revolution disturbance";
    static constexpr const char* keys[] = {"node", "order", "amplitude", "phase"};

    static Spec read(ElementSource& src, const std::string& name) {
        Spec e = spec_at_ends<OrderTorque>(src, name);
        e.order = src.number("order");
        if (!(e.order > 0) || e.order > 1000)
            src.fail("order", "an order is a positive number of cycles per revolution of the node (at most 1000)");
        e.amplitude = src.field("amplitude");
        e.phase = src.field_or("phase", Field::value(0.0));
        return e;
    }

    /// f(info, field...) for each numeric field, of each of e... (a spec first, then bound elements) in step.
    template <class F, class... E>
    static void for_each_field(F&& f, E&... e) {
        f(FieldInfo{"amplitude", nullptr, SignRule::any, "N m"}, e.amplitude...);
        f(FieldInfo{"phase", nullptr, SignRule::any, "rad"}, e.phase...);
    }

    static constexpr ChannelUse channel{};  ///< reads no channel
    static int channel_of(const Spec&) { return -1; }
    static constexpr ElementOutputs outputs = ElementOutputs::torque;

    /// revolution_mean: an excitation, no stiffness (`lin` keeps no amplitude); operating_point:
    /// its slope −A k sin(kθ + φ) there.
    static LinearNote linearise(const Spec&, Spec& lin, const LinearisationPoint& at) {
        if (at.mode != AngleDependence::revolution_mean)
            return {"operating_point", "its slope -A k sin(k theta + phi) at the operating point as a stiffness to ground"};
        lin.amplitude = Field::value(0.0);
        return {"excitation", "an excitation: its angle stiffness averages to zero over a revolution"};
    }

    // ---- the equations of motion

    template <class T>
    static void bind(const Spec& s, Bound<T>& e) {
        e.order = s.order;
    }

    static constexpr bool acts_at_rest = true;  ///< a function of the angle alone
    static constexpr ElementEnds ends = ElementEnds::one_node;

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

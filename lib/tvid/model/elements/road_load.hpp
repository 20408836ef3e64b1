#pragma once
// A vehicle's road load seen through the final drive: rolling resistance, a speed-
// proportional loss and aerodynamic drag on one node.

#include <string>

#include "tvid/model/element_source.hpp"
#include "tvid/model/element_traits.hpp"
#include "tvid/model/elements/node_motion.hpp"
#include "tvid/model/field.hpp"
#include "tvid/model/smooth_sign.hpp"

namespace tvid {

/// Road load on node a: T = a·tanh(ω/ω_s) + b·ω + c·ω·|ω|, which is (a + b·|ω| + c·ω²)·sign(ω)
/// once |ω| is a few ω_s; the torque on the node is −T.
struct RoadLoadSpec {
    std::string name;
    int node = 0;
    Field rolling = Field::value(0.0), viscous = Field::value(0.0), drag = Field::value(0.0);  ///< a, b, c
    Field smoothing_speed = Field::value(0.1);
    bool smoothing_given = false;  ///< smoothing_speed given; else the data choose it (experiment/smoothing_speeds.hpp)
};

namespace elements {

struct RoadLoad {
    using Spec = RoadLoadSpec;
    template <class T>
    struct Bound : OnOneNode {
        T rolling, viscous, drag, smoothing_speed;  ///< a, b, c
        T inverse_smoothing = T(0.0);
    };

    /// The width of the rolling resistance's smoothed sign where nothing else chooses it, as friction's.
    static constexpr double kDefaultSmoothingSpeed = 0.1;

    // ---- the experiment file: `{ type: road_load, node: NODE, a: A, b: B, c: C, smoothing_speed: VS }`
    static constexpr const char* type_name = "road_load";
    static constexpr const char* summary =
        "a road load on a node: (a + b*|omega| + c*omega^2)*sign(omega), the sign smoothed";
    static constexpr const char* keys[] = {"node", "a", "b", "c", "smoothing_speed"};

    static Spec read(ElementSource& src, const std::string& name) {
        Spec e = spec_at_ends<RoadLoad>(src, name);
        if (!src.has("a") && !src.has("b") && !src.has("c"))
            src.fail_missing("a", "(a road load needs a: [N m], b: [N m s/rad] or c: [N m s^2/rad^2])");
        e.rolling = src.field_or("a", Field::value(0.0));
        e.viscous = src.field_or("b", Field::value(0.0));
        e.drag = src.field_or("c", Field::value(0.0));
        e.smoothing_speed = src.field_or("smoothing_speed", Field::value(kDefaultSmoothingSpeed));
        e.smoothing_given = src.has("smoothing_speed");
        return e;
    }

    /// f(info, field...) for each numeric field, of each of e... (a spec first, then bound elements) in step.
    template <class F, class... E>
    static void for_each_field(F&& f, E&... e) {
        f(FieldInfo{"a", "a rolling resistance torque", SignRule::non_negative, "N m"}, e.rolling...);
        f(FieldInfo{"b", "a speed-proportional loss", SignRule::non_negative, "N m s/rad"}, e.viscous...);
        f(FieldInfo{"c", "a drag coefficient", SignRule::non_negative, "N m s^2/rad^2"}, e.drag...);
        f(FieldInfo{"smoothing_speed", "a smoothing speed", SignRule::positive, "rad/s"}, e.smoothing_speed...);
    }

    static constexpr ChannelUse channel{};  ///< reads no channel
    static int channel_of(const Spec&) { return -1; }
    static constexpr ElementOutputs outputs = ElementOutputs::torque;

    /// Enters with its slope dT/dω at the operating point's speed: b + 2c|ω| (and a/ω_s at rest).
    static LinearNote linearise(const Spec& s, Spec&, const LinearisationPoint& at) {
        const double w = at.x[at.node_names.size() + static_cast<std::size_t>(s.node)];
        const double t = std::tanh(w / at.value(s.smoothing_speed));
        const double slope = at.value(s.rolling) * (1 - t * t) / at.value(s.smoothing_speed) + at.value(s.viscous) +
                             2 * at.value(s.drag) * std::abs(w);
        return {"operating_point", "road load's slope at " + linear_number(w) + " rad/s: dT/domega = " +
                                       linear_number(slope) + " N m s/rad"};
    }

    // ---- the equations of motion

    template <class T>
    static void bind(const Spec&, Bound<T>& e) {
        e.inverse_smoothing = T(1.0) / e.smoothing_speed;
    }

    static constexpr bool acts_at_rest = false;  ///< no torque at zero speed
    static constexpr ElementEnds ends = ElementEnds::one_node;

    template <class T>
    [[gnu::always_inline]] static T torque(const Bound<T>& e, const NodeMotion<T>& m) {
        using std::abs;
        const T w = m.twist_rate(e.node, kGround);
        return e.rolling * smooth_sign(w * e.inverse_smoothing) + (e.viscous + e.drag * abs(w)) * w;
    }

    template <class T>
    [[gnu::always_inline]] static void load(const Bound<T>& e, const T& t, const NodeMotion<T>&, T* node_torque) {
        node_torque[e.node] -= t;
    }
};

}  // namespace elements
}  // namespace tvid

#pragma once
// A rigid gear between two nodes: no compliance and no node of its own (Modelica's
// IdealGear, Simscape's Simple Gear), lossless or with an efficiency.

#include <string>

#include "tvid/model/element_source.hpp"
#include "tvid/model/element_traits.hpp"
#include "tvid/model/elements/gear_efficiency.hpp"
#include "tvid/model/elements/node_motion.hpp"
#include "tvid/model/field.hpp"
#include "tvid/model/field_bounds.hpp"
#include "tvid/model/smooth_sign.hpp"

namespace tvid {

/// A rigid gear of ratio n from a to b: θa = n·θb. It ties its nodes kinematically, so
/// it has no torque law of its own: the torque τ it takes from a (and gives b as n·τ·f)
/// is whatever keeps ωa = n·ωb (model/rigid_gears.hpp eliminates it). With an efficiency
/// η, f = η^tanh(P/P_s), P = τ·ωa the power a gives the gear: η when a drives b, 1/η when
/// b drives a (the loss acts on the transmitted torque by the direction of power flow).
struct IdealGearSpec {
    std::string name;
    int a = 0, b = 0;
    Field ratio;
    bool lossy = false;  ///< efficiency given
    Field efficiency = Field::value(1.0), smoothing_power = Field::value(1.0);
};

namespace elements {

struct IdealGear {
    using Spec = IdealGearSpec;
    template <class T>
    struct Bound : BetweenTwoNodes, gear_efficiency::BoundPart<T> {
        T ratio;
    };

    /// The power over which a lossy gear's factor passes from 1/η to η [W], as gear_mesh's.
    static constexpr double kDefaultSmoothingPower = 1.0;

    // ---- the experiment file: `{ type: ideal_gear, between: [a, b], ratio: N }`, losses with
    // `efficiency` (0 < η ≤ 1) and `smoothing_power`
    static constexpr const char* type_name = "ideal_gear";
    static constexpr const char* summary =
        "a rigid gear between two nodes (theta_a = ratio * theta_b; no compliance, no node of its own), lossless or "
        "with an efficiency on the transmitted torque by the direction of power flow";
    static constexpr const char* keys[] = {"between", "ratio", "efficiency", "smoothing_power"};

    static Spec read(ElementSource& src, const std::string& name) {
        Spec e = spec_at_ends<IdealGear>(src, name);
        gear_efficiency::read(src, e, "gear", kDefaultSmoothingPower);
        return e;
    }

    static void check(const Spec& e, const FieldBounds& b) { gear_efficiency::check(e, b); }

    template <class F, class Spec_, class... E>
    static void for_each_field(F&& f, Spec_& s, E&... e) {
        f(FieldInfo{"ratio", "a gear ratio", SignRule::nonzero, "1"}, s.ratio, e.ratio...);
        gear_efficiency::for_each_field(f, s, e...);
    }

    static constexpr ChannelUse channel{};  ///< reads no channel
    static int channel_of(const Spec&) { return -1; }
    /// No torque output: the torque it transmits is a constraint's (measure a shaft beside it).
    static constexpr ElementOutputs outputs = ElementOutputs::none;

    /// The linearisation sees the reduced line (one coordinate for both nodes); a lossy gear
    /// at its operating point's direction of power flow.
    static LinearNote linearise(const Spec& e, Spec&, const LinearisationPoint& at) {
        const std::string ratio = linear_number(at.value(e.ratio));
        if (!e.lossy) return {"exact", "rigid (ratio " + ratio + "): its nodes share one coordinate"};
        return {"operating_point", "rigid (ratio " + ratio + "), efficiency " + linear_number(at.value(e.efficiency)) +
                                       " by the operating point's direction of power flow"};
    }

    // ---- the equations of motion: no torque law; model/rigid_gears.hpp ties the nodes

    template <class T>
    static void bind(const Spec& s, Bound<T>& e) {
        gear_efficiency::bind(s, e);
    }

    static constexpr bool acts_at_rest = true;  ///< it ties its nodes at rest too
    static constexpr ElementEnds ends = ElementEnds::geared;

    template <class T>
    [[gnu::always_inline]] static T torque(const Bound<T>&, const NodeMotion<T>&) {
        return T(0);
    }
    template <class T>
    [[gnu::always_inline]] static void load(const Bound<T>&, const T&, const NodeMotion<T>&, T*) {}
};

}  // namespace elements
}  // namespace tvid

#pragma once
// Friction of a node to ground, or between two nodes (a slipping clutch, a damper's
// hysteresis): viscous, and optionally dry (Coulomb) with a Stribeck rise at low speed,
// each allowed to differ with the direction of motion.

#include <string>
#include <tuple>

#include "tvid/model/element_source.hpp"
#include "tvid/model/element_traits.hpp"
#include "tvid/model/elements/node_motion.hpp"
#include "tvid/model/elements/two_node_load.hpp"
#include "tvid/model/field.hpp"
#include "tvid/model/field_bounds.hpp"
#include "tvid/model/smooth_sign.hpp"

namespace tvid {

/// Friction on the relative speed v = ωa − ωb (ωa for b = ground). Viscous only: T = c·v.
/// With dry friction, after Simscape's Rotational Friction with the sign smoothed:
///   s = tanh(v/v_s), p = (1 + s)/2 (0 turning backwards, 1 forwards),
///   T = c(p)·v + (Fc(p) + (F_brk − Fc)·exp(−(v/v_st)²))·s,
///   c(p) = c⁻ + (c − c⁻)·p,  Fc(p) = Fc⁻ + (Fc − Fc⁻)·p.
/// Torque −T on a, +T on b.
struct FrictionSpec {
    std::string name;
    int a = 0;
    Field c = Field::value(0.0);
    int b = kGround;
    Field c_negative = Field::value(0.0);
    Field coulomb = Field::value(0.0), coulomb_negative = Field::value(0.0);
    Field breakaway = Field::value(0.0), stribeck_speed = Field::value(1.0);
    Field smoothing_speed = Field::value(0.1);
    bool smoothing_given = false;  ///< smoothing_speed given; else the data choose it (experiment/smoothing_speeds.hpp)
    bool dry = false;         ///< coulomb or breakaway given: the smoothed sign enters
    bool asymmetric = false;  ///< c_negative or coulomb_negative given
    bool stribeck = false;    ///< breakaway given (with stribeck_speed)
};

namespace elements {

struct Friction : TwoNodeLoad {  // its load: −t on a, +t on b
    using Spec = FrictionSpec;
    template <class T>
    struct Bound : BetweenTwoNodes {
        T c, c_negative, coulomb, coulomb_negative, breakaway, stribeck_speed, smoothing_speed;
        bool smooth = false;  ///< the smoothed sign enters (dry or asymmetric)
        bool stribeck = false;
        T inverse_smoothing = T(0.0), inverse_stribeck = T(0.0), rise = T(0.0);  ///< 1/v_s, 1/v_st, F_brk − Fc
    };

    /// The width of the sign's smoothing [rad/s or m/s] where nothing else chooses it: in an
    /// experiment, 1 % of the largest speed its recordings show at the element's nodes
    /// (experiment/smoothing_speeds.hpp); this where they show none (dT/dv at v = 0 is
    /// c + F_brk/v_s: a smaller width is a stiffer law).
    static constexpr double kDefaultSmoothingSpeed = 0.1;

    // ---- the experiment file: `{ type: friction, node: NODE, c: C }` or `between: [a, b]`, with
    // the dry friction's `coulomb`, `breakaway` and `stribeck_speed`, `smoothing_speed`, and
    // `c_negative`, `coulomb_negative` for the backward direction
    static constexpr const char* type_name = "friction";
    static constexpr const char* summary =
        "friction of a node to ground or between two nodes: viscous, and dry (Coulomb, Stribeck) "
        "with a smoothed sign, each direction its own";
    static constexpr const char* keys[] = {"node",          "between",         "c",
                                           "c_negative",    "coulomb",         "coulomb_negative",
                                           "breakaway",     "stribeck_speed",  "smoothing_speed"};

    static Spec read(ElementSource& src, const std::string& name) {
        Spec e;
        e.name = name;
        if (src.has("between")) {
            if (src.has("node")) src.fail("between", "friction acts on node: (to ground) or between: [a, b], not both");
            std::tie(e.a, e.b) = src.between(true);
        } else {
            e.a = src.node("node");
        }
        e.dry = src.has("coulomb") || src.has("breakaway");
        if (!e.dry && !src.has("c"))
            src.fail_missing("c", "(a viscous coefficient [N m s/rad], or coulomb: a dry friction torque [N m])");
        e.c = src.field_or("c", Field::value(0.0));
        e.coulomb = src.field_or("coulomb", Field::value(0.0));
        e.asymmetric = src.has("c_negative") || src.has("coulomb_negative");
        e.c_negative = src.field_or("c_negative", e.c);
        if (src.has("coulomb_negative") && !e.dry)
            src.fail("coulomb_negative", "the backward direction's dry friction needs coulomb: (the forward one's)");
        e.coulomb_negative = src.field_or("coulomb_negative", e.coulomb);
        e.stribeck = src.has("breakaway");
        if (e.stribeck != src.has("stribeck_speed"))
            src.fail(e.stribeck ? "breakaway" : "stribeck_speed",
                     "the Stribeck rise needs both breakaway: [N m] and stribeck_speed: [rad/s]");
        e.breakaway = src.field_or("breakaway", e.coulomb);
        e.stribeck_speed = src.field_or("stribeck_speed", Field::value(1.0));
        if (src.has("smoothing_speed") && !e.dry && !e.asymmetric)
            src.fail("smoothing_speed", "smooths the sign of dry or direction-dependent friction: give coulomb: or c_negative:");
        e.smoothing_speed = src.field_or("smoothing_speed", Field::value(kDefaultSmoothingSpeed));
        e.smoothing_given = src.has("smoothing_speed");
        return e;
    }

    /// After the sign rules: the breakaway torque is the peak of the Stribeck curve, at
    /// least the Coulomb torque (both constants; parameters are held by their bounds).
    static void check(const Spec& e, const FieldBounds& b) {
        if (e.stribeck && b.known(e.breakaway) && b.known(e.coulomb) &&
            b.highest(e.breakaway) < b.lowest(e.coulomb))
            b.fail("breakaway", {e.breakaway, e.coulomb},
                   "must be at least coulomb (" + b.text(e.coulomb) + " N m), got " + b.text(e.breakaway));
    }

    /// f(info, field...) for each numeric field, of each of s, e... (a spec first, then bound elements) in step.
    template <class F, class Spec_, class... E>
    static void for_each_field(F&& f, Spec_& s, E&... e) {
        const bool smooth = s.dry || s.asymmetric;
        f(FieldInfo{"c", "a friction coefficient", SignRule::non_negative, "N m s/rad"}, s.c, e.c...);
        f(FieldInfo{"c_negative", "a friction coefficient", SignRule::non_negative, "N m s/rad", s.asymmetric},
          s.c_negative, e.c_negative...);
        f(FieldInfo{"coulomb", "a dry friction torque", SignRule::non_negative, "N m", s.dry}, s.coulomb, e.coulomb...);
        f(FieldInfo{"coulomb_negative", "a dry friction torque", SignRule::non_negative, "N m", s.dry && s.asymmetric},
          s.coulomb_negative, e.coulomb_negative...);
        f(FieldInfo{"breakaway", "a breakaway torque", SignRule::non_negative, "N m", s.stribeck}, s.breakaway,
          e.breakaway...);
        f(FieldInfo{"stribeck_speed", "a Stribeck speed", SignRule::positive, "rad/s", s.stribeck}, s.stribeck_speed,
          e.stribeck_speed...);
        f(FieldInfo{"smoothing_speed", "a smoothing speed", SignRule::positive, "rad/s", smooth}, s.smoothing_speed,
          e.smoothing_speed...);
    }

    static constexpr ChannelUse channel{};  ///< reads no channel
    static int channel_of(const Spec&) { return -1; }
    static constexpr ElementOutputs outputs = ElementOutputs::torque;

    /// Viscous friction is linear. Dry or direction-dependent friction enters with its slope
    /// dT/dv at the operating point's relative speed (at rest: c + F_brk/v_s, a stiff damper
    /// that stands for sticking).
    static LinearNote linearise(const Spec& s, Spec&, const LinearisationPoint& at) {
        if (!s.dry && !s.asymmetric) return {"exact", "linear"};
        Bound<double> e;
        for_each_field([&](const FieldInfo&, const Field& field, double& value) { value = at.value(field); }, s, e);
        bind(s, e);
        const std::size_t n = at.node_names.size();
        const double v = at.x[n + static_cast<std::size_t>(s.a)] - (s.b == kGround ? 0.0 : at.x[n + static_cast<std::size_t>(s.b)]);
        const double h = 1e-6 * (std::abs(v) + at.value(s.smoothing_speed));
        const double slope = (law(e, v + h) - law(e, v - h)) / (2 * h);
        return {"operating_point", "friction law's slope at relative speed " + linear_number(v) +
                                       " rad/s: dT/dv = " + linear_number(slope) + " N m s/rad"};
    }

    // ---- the equations of motion

    template <class T>
    static void bind(const Spec& s, Bound<T>& e) {
        e.smooth = s.dry || s.asymmetric;
        e.stribeck = s.stribeck;
        e.inverse_smoothing = T(1.0) / e.smoothing_speed;
        e.inverse_stribeck = T(1.0) / e.stribeck_speed;
        e.rise = e.breakaway - e.coulomb;
    }

    static constexpr bool acts_at_rest = false;  ///< no torque at zero speed
    static constexpr ElementEnds ends = ElementEnds::two_nodes;

    /// The friction torque at relative speed v.
    template <class T>
    [[gnu::always_inline]] static T law(const Bound<T>& e, const T& v) {
        if (!e.smooth) return e.c * v;
        const T s = smooth_sign(v * e.inverse_smoothing);
        const T p = T(0.5) * (T(1.0) + s);
        const T c = e.c_negative + (e.c - e.c_negative) * p;
        T dry = e.coulomb_negative + (e.coulomb - e.coulomb_negative) * p;
        if (e.stribeck) {
            const T r = v * e.inverse_stribeck;
            dry = dry + e.rise * math::exp(-(r * r));
        }
        return c * v + dry * s;
    }

    template <class T>
    [[gnu::always_inline]] static T torque(const Bound<T>& e, const NodeMotion<T>& m) {
        return law(e, m.twist_rate(e.a, e.b));
    }
};

}  // namespace elements
}  // namespace tvid

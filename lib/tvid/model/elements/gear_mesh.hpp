#pragma once
// A gear mesh between two nodes, stiff and damped or with backlash.

#include <cmath>
#include <string>

#include "tvid/model/element_source.hpp"
#include "tvid/model/element_traits.hpp"
#include "tvid/model/elements/clearance.hpp"
#include "tvid/model/elements/gear_efficiency.hpp"
#include "tvid/model/elements/node_motion.hpp"
#include "tvid/model/field.hpp"
#include "tvid/model/field_bounds.hpp"
#include "tvid/model/smooth_clearance.hpp"
#include "tvid/model/smooth_sign.hpp"

namespace tvid {

/// Gear mesh between a and b with ratio n: twist θa − n·θb; mesh torque T = k·twist + c·twist'
/// (or the clearance law when `has_clearance`); torque −T on a and +n·T·f on b. A lossless
/// mesh has f = 1; one with efficiency η loses (1 − η) of the power where it flows:
/// f = η^tanh(P/P_s) with P = T·ωa the power a gives the mesh (η when a drives b, 1/η when
/// b drives a, 1 through zero power over the smoothing power P_s).
struct GearMeshSpec {
    std::string name;
    int a = 0, b = 0;
    Field ratio, k, c;
    bool has_clearance = false;
    Field k_minus, k_plus, c_minus, c_plus, mu, sigma;  ///< used when has_clearance
    bool smooth = true;                                 ///< false: no sigma, eq. 7
    bool lossy = false;                                 ///< efficiency given
    Field efficiency = Field::value(1.0), smoothing_power = Field::value(1.0);
};

namespace elements {

struct GearMesh {
    using Spec = GearMeshSpec;
    template <class T>
    struct Bound : ClearanceLaw<T>, BetweenTwoNodes, gear_efficiency::BoundPart<T> {  ///< ClearanceLaw: with has_clearance
        T ratio, k, c;
        bool has_clearance = false;
    };

    /// The default power over which a lossy mesh's factor passes from 1/η to η [W]: small
    /// beside a powertrain's kilowatts.
    static constexpr double kDefaultSmoothingPower = 1.0;

    // ---- the experiment file: `{ type: gear_mesh, between: [a, b], ratio: N, k: K, c: C }`, with backlash
    // `mu` and the clearance law's keys (k and c stand for both signs'), losses with `efficiency`
    // (0 < η ≤ 1) and `smoothing_power`
    static constexpr const char* type_name = "gear_mesh";
    static constexpr const char* summary =
        "a gear mesh between two nodes with a ratio, stiff and damped or with backlash, lossless or with an efficiency";
    static constexpr const char* keys[] = {"between", "ratio",  "k",  "c",     "k_minus",    "k_plus",
                                           "c_minus", "c_plus", "mu", "sigma", "efficiency", "smoothing_power"};

    static Spec read(ElementSource& src, const std::string& name) {
        Spec e = spec_at_ends<GearMesh>(src, name);
        e.has_clearance = src.has("mu");
        e.c = src.field_or("c", Field::value(0.0));
        if (!e.has_clearance) {
            for (const char* key : {"k_minus", "k_plus", "c_minus", "c_plus", "sigma"})
                if (src.has(key)) src.fail(key, "clearance fields need mu (the half backlash)");
            e.k = src.field("k");
        } else {
            e.k = src.field_or("k", Field{});
            read_clearance_law(src, e, src.has("k") ? &e.k : nullptr, &e.c);
        }
        gear_efficiency::read(src, e, "mesh", kDefaultSmoothingPower);
        return e;
    }

    static void check(const Spec& e, const FieldBounds& b) { gear_efficiency::check(e, b); }

    /// f(info, field...) for each numeric field, of each of s, e... (a spec first, then bound elements) in step.
    template <class F, class Spec_, class... E>
    static void for_each_field(F&& f, Spec_& s, E&... e) {
        f(FieldInfo{"ratio", "a gear ratio", SignRule::nonzero, "1"}, s.ratio, e.ratio...);
        f(FieldInfo{"k", "a mesh stiffness", SignRule::non_negative, "N m/rad"}, s.k, e.k...);
        f(FieldInfo{"c", "a mesh damping coefficient", SignRule::non_negative, "N m s/rad"}, s.c, e.c...);
        for_each_clearance_law_field(f, s.has_clearance, s.smooth, s, e...);
        gear_efficiency::for_each_field(f, s, e...);
    }

    static constexpr ChannelUse channel{};  ///< reads no channel
    static int channel_of(const Spec&) { return -1; }
    static constexpr ElementOutputs outputs = ElementOutputs::torque_each_side;

    /// Linear without backlash; with it, the backlash law's slopes at the mesh twist θa − n·θb.
    static LinearNote linearise(const Spec& e, Spec&, const LinearisationPoint& at) {
        const double ratio = at.value(e.ratio);
        if (e.has_clearance)
            return {"operating_point",
                    "backlash law linearised at the mesh twist " + linear_number(at.twist(e.a, e.b, ratio)) + " rad"};
        if (e.lossy) {
            const std::size_t n = at.node_names.size();
            const double wa = at.x[n + static_cast<std::size_t>(e.a)], wb = at.x[n + static_cast<std::size_t>(e.b)];
            const double t = at.value(e.k) * at.twist(e.a, e.b, ratio) + at.value(e.c) * (wa - ratio * wb);
            const double f = std::pow(at.value(e.efficiency), std::tanh(t * wa / at.value(e.smoothing_power)));
            return {"operating_point", "ratio " + linear_number(ratio) + ", efficiency " +
                                           linear_number(at.value(e.efficiency)) + ": output side n*T*f with f = " +
                                           linear_number(f) + " at the power " + linear_number(t * wa) + " W"};
        }
        return {"exact", "linear (ratio " + linear_number(ratio) + ")"};
    }

    // ---- the equations of motion

    template <class T>
    static void bind(const Spec& s, Bound<T>& e) {
        e.has_clearance = s.has_clearance;
        e.smooth = s.smooth;
        e.prepare();
        gear_efficiency::bind(s, e);
    }

    /// The factor f = η^tanh(P/P_s) of the output side's torque n·T·f (1 at rest).
    template <class T>
    [[gnu::always_inline]] static T loss_factor(const Bound<T>& e, const T& t, const NodeMotion<T>& m) {
        if (!m.moving()) return T(1.0);
        return math::exp(smooth_sign(t * m.omega[e.a] * e.inverse_smoothing_power) * e.log_efficiency);
    }

    static constexpr bool acts_at_rest = true;
    static constexpr ElementEnds ends = ElementEnds::geared;

    /// The mesh torque T of the twist θa − n·θb.
    template <class T>
    [[gnu::always_inline]] static T torque(const Bound<T>& e, const NodeMotion<T>& m) {
        const T twist = m.theta[e.a] - e.ratio * m.theta[e.b];
        const T rate = m.moving() ? m.omega[e.a] - e.ratio * m.omega[e.b] : T(0);
        return e.has_clearance ? e.ClearanceLaw<T>::torque(twist, rate) : e.k * twist + e.c * rate;
    }

    template <class T>
    [[gnu::always_inline]] static void load(const Bound<T>& e, const T& t, const NodeMotion<T>& m, T* node_torque) {
        node_torque[e.a] -= t;                            // mesh torque T on a
        node_torque[e.b] += output_side_torque(e, t, m);  // and n·T·f on b
    }

    /// The torque on the output shaft b of mesh torque t: n·T·f (a transducer on the
    /// output shaft reads this).
    template <class T>
    [[gnu::always_inline]] static T output_side_torque(const Bound<T>& e, const T& t, const NodeMotion<T>& m) {
        if (!e.lossy) return e.ratio * t;
        return e.ratio * t * loss_factor(e, t, m);
    }
};

}  // namespace elements
}  // namespace tvid

#pragma once
// The smoothed impact model with a clearance between two nodes, or a node and ground
// (Yoshida & Takamatsu eqs. 7–11).

#include <string>

#include "tvid/model/elements/node_motion.hpp"
#include "tvid/model/field.hpp"
#include "tvid/model/smooth_clearance.hpp"

namespace tvid {

/// Smoothed impact model with a clearance (Yoshida & Takamatsu eqs. 8–11) on the twist θa − θb.
/// Transmitted torque F = Gσ(θ) + Hσ(θ)·θ'; torque on a is −F, on b +F.
/// `smooth == false` selects the non-smooth law of eq. 7.
struct ClearanceSpec {
    std::string name;
    int a = 0, b = kGround;
    Field k_minus, k_plus, c_minus, c_plus, mu, sigma;
    bool smooth = true;
};

namespace elements {

/// The six fields of the clearance law (also a gear mesh's, when it has backlash);
/// `in_use` false marks all of them unused, and σ is unused by the non-smooth law.
template <class F, class... E>
void for_each_clearance_law_field(F& f, bool in_use, bool smooth, E&... e) {
    f(FieldInfo{"k_minus", "a contact stiffness", SignRule::non_negative, in_use}, e.k_minus...);
    f(FieldInfo{"k_plus", "a contact stiffness", SignRule::non_negative, in_use}, e.k_plus...);
    f(FieldInfo{"c_minus", "a contact damping coefficient", SignRule::non_negative, in_use}, e.c_minus...);
    f(FieldInfo{"c_plus", "a contact damping coefficient", SignRule::non_negative, in_use}, e.c_plus...);
    f(FieldInfo{"mu", "a half backlash", SignRule::non_negative, in_use}, e.mu...);
    f(FieldInfo{"sigma", "the smoothing steepness sigma", SignRule::positive, in_use && smooth}, e.sigma...);
}

struct Clearance {
    using Spec = ClearanceSpec;
    template <class T>
    struct Bound : ClearanceLaw<T> {
        int a = 0, b = kGround;
    };

    /// f(info, field...) for each numeric field, of each of s, e... (a spec first, then bound elements) in step.
    template <class F, class Spec_, class... E>
    static void for_each_field(F&& f, Spec_& s, E&... e) {
        for_each_clearance_law_field(f, true, s.smooth, s, e...);
    }

    template <class T>
    static void bind(const Spec& s, Bound<T>& e) {
        e.a = s.a;
        e.b = s.b;
        e.smooth = s.smooth;
        e.prepare();
    }

    static constexpr bool acts_at_rest = true;

    /// The torque transmitted from a to b: Fσ(θa − θb, ωa − ωb).
    template <class T>
    [[gnu::always_inline]] static T torque(const Bound<T>& e, const NodeMotion<T>& m) {
        return e.ClearanceLaw<T>::torque(m.twist(e.a, e.b), m.twist_rate(e.a, e.b));
    }

    template <class T>
    [[gnu::always_inline]] static void load(const Bound<T>& e, const T& t, const NodeMotion<T>&, T* node_torque) {
        node_torque[e.a] -= t;
        if (e.b != kGround) node_torque[e.b] += t;
    }
};

}  // namespace elements
}  // namespace tvid

#pragma once
// The smoothed impact model with a clearance between two nodes, or a node and ground
// (Yoshida & Takamatsu eqs. 7–11).

#include <string>

#include "tvid/model/element_source.hpp"
#include "tvid/model/element_traits.hpp"
#include "tvid/model/elements/node_motion.hpp"
#include "tvid/model/elements/two_node_load.hpp"
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
    f(FieldInfo{"k_minus", "a contact stiffness", SignRule::non_negative, "N m/rad", in_use, "k"}, e.k_minus...);
    f(FieldInfo{"k_plus", "a contact stiffness", SignRule::non_negative, "N m/rad", in_use, "k"}, e.k_plus...);
    f(FieldInfo{"c_minus", "a contact damping coefficient", SignRule::non_negative, "N m s/rad", in_use, "c"},
      e.c_minus...);
    f(FieldInfo{"c_plus", "a contact damping coefficient", SignRule::non_negative, "N m s/rad", in_use, "c"},
      e.c_plus...);
    f(FieldInfo{"mu", "a half backlash", SignRule::non_negative, "rad", in_use}, e.mu...);
    f(FieldInfo{"sigma", "the smoothing steepness sigma", SignRule::positive, "1/rad", in_use && smooth}, e.sigma...);
}

/// The experiment file's keys of a clearance law.
inline constexpr const char* kClearanceLawKeys[] = {"k_minus", "k_plus", "c_minus", "c_plus", "mu", "sigma"};

/// Reads the six fields of a clearance law into s (a clearance's or a gear mesh's spec):
/// k_minus and k_plus default to the shorthand k, c_minus and c_plus to c (when not null);
/// without sigma the law is the non-smooth one of eq. 7.
template <class S>
void read_clearance_law(const ElementSource& src, S& s, const Field* k, const Field* c) {
    auto stiffness = [&](const char* key) {
        if (!src.has(key) && k == nullptr) src.fail_missing(key);
        return src.has(key) ? src.field(key) : *k;
    };
    auto damping = [&](const char* key) {
        if (!src.has(key) && c == nullptr) src.fail_missing(key);
        return src.has(key) ? src.field(key) : *c;
    };
    s.k_minus = stiffness("k_minus");
    s.k_plus = stiffness("k_plus");
    s.c_minus = damping("c_minus");
    s.c_plus = damping("c_plus");
    s.mu = src.field("mu");
    s.smooth = src.has("sigma");
    if (s.smooth) s.sigma = src.field("sigma");
}

struct Clearance : TwoNodeLoad {  // its load: −t on a, +t on b
    using Spec = ClearanceSpec;
    template <class T>
    struct Bound : ClearanceLaw<T>, BetweenTwoNodes {
    };

    // ---- the experiment file: `{ type: clearance, between: [a, b], k_minus, k_plus, c_minus, c_plus, mu, sigma }`
    // (k and c stand for both signs' stiffness and damping; without sigma the non-smooth law)
    static constexpr const char* type_name = "clearance";
    static constexpr const char* summary = "a spring and damper through a smoothed clearance (backlash) between two nodes or a node and ground (Yoshida & Takamatsu eqs. 7-11)";
    static constexpr const char* keys[] = {"between", "k", "c", "k_minus", "k_plus", "c_minus", "c_plus", "mu", "sigma"};

    static Spec read(ElementSource& src, const std::string& name) {
        Spec e = spec_at_ends<Clearance>(src, name);
        const Field k = src.field_or("k", Field{}), c = src.field_or("c", Field::value(0.0));
        read_clearance_law(src, e, src.has("k") ? &k : nullptr, &c);
        return e;
    }

    /// f(info, field...) for each numeric field, of each of s, e... (a spec first, then bound elements) in step.
    template <class F, class Spec_, class... E>
    static void for_each_field(F&& f, Spec_& s, E&... e) {
        for_each_clearance_law_field(f, true, s.smooth, s, e...);
    }

    static constexpr ChannelUse channel{};  ///< reads no channel
    static int channel_of(const Spec&) { return -1; }
    static constexpr ElementOutputs outputs = ElementOutputs::torque;

    /// The clearance law's slopes at the operating point's twist.
    static LinearNote linearise(const Spec& e, Spec&, const LinearisationPoint& at) {
        return {"operating_point", std::string(e.smooth ? "smooth" : "non-smooth") +
                                       " clearance law linearised at the twist " + linear_number(at.twist(e.a, e.b)) +
                                       " rad between " + at.node_name(e.a) + " and " + at.node_name(e.b)};
    }

    // ---- the equations of motion

    template <class T>
    static void bind(const Spec& s, Bound<T>& e) {
        e.smooth = s.smooth;
        e.prepare();
    }

    static constexpr bool acts_at_rest = true;
    static constexpr ElementEnds ends = ElementEnds::two_nodes;

    /// The torque transmitted from a to b: Fσ(θa − θb, ωa − ωb).
    template <class T>
    [[gnu::always_inline]] static T torque(const Bound<T>& e, const NodeMotion<T>& m) {
        return e.ClearanceLaw<T>::torque(m.twist(e.a, e.b), m.twist_rate(e.a, e.b));
    }
};

}  // namespace elements
}  // namespace tvid

#pragma once
// A gear's efficiency, as both geared kinds (ideal_gear, gear_mesh) read, check, list and
// bind it: η (0 < η ≤ 1) and the power P_s over which the factor f = η^tanh(P/P_s) on the
// output side's torque passes from 1/η (b drives a) to η (a drives b). Each kind's spec and
// bound element hold `lossy`, `efficiency` and `smoothing_power`; the bound one also
// `log_efficiency` and `inverse_smoothing_power` (BoundPart).

#include <string>

#include "tvid/model/smooth_sign.hpp"  // math::log1p for double, dual numbers and packs
#include "tvid/model/element_source.hpp"
#include "tvid/model/field.hpp"
#include "tvid/model/field_bounds.hpp"

namespace tvid::elements::gear_efficiency {

/// What a bound geared element holds of its efficiency (its Bound derives from it).
template <class T>
struct BoundPart {
    T efficiency = T(1.0), smoothing_power = T(1.0);
    bool lossy = false;
    T log_efficiency = T(0.0), inverse_smoothing_power = T(0.0);  ///< ln η, 1/P_s
};

/// `efficiency` and `smoothing_power` into e, lossy when an efficiency is given; `what`
/// names the element in a message ("gear", "mesh").
template <class Spec>
void read(ElementSource& src, Spec& e, const char* what, double default_smoothing_power) {
    e.lossy = src.has("efficiency");
    if (src.has("smoothing_power") && !e.lossy)
        src.fail("smoothing_power", std::string("smooths a lossy ") + what + "'s power flow: give efficiency:");
    e.efficiency = src.field_or("efficiency", Field::value(1.0));
    e.smoothing_power = src.field_or("smoothing_power", Field::value(default_smoothing_power));
}

/// After the sign rules: an efficiency is at most 1 (a parameter is held by its bounds).
template <class Spec>
void check(const Spec& e, const FieldBounds& b) {
    if (e.lossy && b.known(e.efficiency) && b.highest(e.efficiency) > 1.0)
        b.fail("efficiency", {e.efficiency}, "must be at most 1 (got " + b.text(e.efficiency) + ")");
}

/// The two fields, in use when the gear is lossy, as the kind's for_each_field lists them.
template <class F, class Spec_, class... E>
void for_each_field(F& f, Spec_& s, E&... e) {
    f(FieldInfo{"efficiency", "an efficiency", SignRule::positive, "1", s.lossy}, s.efficiency, e.efficiency...);
    f(FieldInfo{"smoothing_power", "a smoothing power", SignRule::positive, "W", s.lossy}, s.smoothing_power,
      e.smoothing_power...);
}

/// ln η and 1/P_s of a bound element whose efficiency and smoothing power are bound.
template <class Spec, class Bound>
void bind(const Spec& s, Bound& e) {
    e.lossy = s.lossy;
    if (s.lossy) {
        e.log_efficiency = math::log1p(e.efficiency - decltype(e.efficiency)(1.0));
        e.inverse_smoothing_power = decltype(e.efficiency)(1.0) / e.smoothing_power;
    }
}

}  // namespace tvid::elements::gear_efficiency

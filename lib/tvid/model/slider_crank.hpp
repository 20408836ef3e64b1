#pragma once
// Piston kinematics of a slider-crank (the methodology paper eq. 4; docs/model-library.md, preset engine_block),
// written once for any scalar type. φ is the crank angle from the cylinder's top dead
// centre, r the crank radius, l the connecting-rod length.
//
//   s(φ)   = r(1 − cos φ) + l − √(l² − r² sin²φ)                 piston travel from TDC
//   s'(φ)  = r sin φ + r² sin 2φ / (2√(l² − r² sin²φ))
//   s''(φ) = r cos φ + r² cos 2φ / √D + r⁴ sin² 2φ / (4 D^{3/2}),  D = l² − r² sin²φ
//
// The methodology paper eq. 4 prints sin²(2θ) under the root; that is a typo: the geometry gives sin²φ.

#include <cmath>

#include "tvid/model/dual.hpp"
#include "tvid/model/packed_dual.hpp"
#include "tvid/simd/elementary_functions.hpp"

namespace tvid {

template <class T>
struct SliderCrankMotion {
    T s;    ///< piston travel from TDC [m]
    T ds;   ///< ds/dφ [m/rad]: the lever arm of the piston force
    T dds;  ///< d²s/dφ² [m/rad²]
};

template <class T, class R>
[[gnu::always_inline]] inline SliderCrankMotion<T> slider_crank(const T& phi, const R& r, const R& l) {
    using std::sqrt;
    T sn, cs;
    math::sincos(phi, sn, cs);
    const T sin2 = 2 * sn * cs, cos2 = cs * cs - sn * sn;
    const T d = l * l - r * r * sn * sn;
    const T root = sqrt(d);
    const T inverse_root = 1 / root;  // one division for the three quotients
    const auto r2 = r * r;
    SliderCrankMotion<T> m;
    m.s = r * (1 - cs) + l - root;
    m.ds = r * sn + r2 * sin2 * inverse_root * 0.5;
    m.dds = r * cs + r2 * cos2 * inverse_root + r2 * r2 * sin2 * sin2 * (inverse_root * inverse_root * inverse_root) * 0.25;
    return m;
}

}  // namespace tvid

#pragma once
// The smoothed sign of the dry-friction and loss laws, tanh(x), written once for any scalar
// type T with tvid's own exponential, so that double, the dual numbers of the sensitivities
// and every lane of a pack give the same bits.

#include <cmath>

#include "tvid/model/dual.hpp"
#include "tvid/model/packed_dual.hpp"
#include "tvid/simd/elementary_functions.hpp"
#include "tvid/simd/pack.hpp"
#include "tvid/simd/select.hpp"

namespace tvid {

/// tanh(x) = sign(x)·(1 − e)/(1 + e) with e = e^{−2|x|} in (0, 1], so nothing overflows
/// however large |x| is.
template <class T>
[[gnu::always_inline]] inline T smooth_sign(const T& x) {
    using std::abs;
    const T e = math::exp(T(-2.0) * abs(x));
    const T t = (T(1.0) - e) / (T(1.0) + e);
    return select(x >= T(0.0), t, -t);
}

}  // namespace tvid

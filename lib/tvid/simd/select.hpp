#pragma once
// select(condition, a, b): the branch of the model code written so that it runs lane by
// lane on packs (tvid/simd/pack.hpp defines it for a Mask and two packs). For double and
// the dual numbers it is the conditional operator. Both a and b are evaluated.

namespace tvid {

template <class T>
T select(bool condition, const T& a, const T& b) {
    return condition ? a : b;
}

}  // namespace tvid

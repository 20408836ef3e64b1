#pragma once
// The plain double inside a scalar of the model code: the number itself for double, the
// value part of a derivative-carrying type. Used where the model branches on a value
// (table lookups), never where a derivative must flow.

namespace tvid {

inline double scalar_value(double x) { return x; }

template <class T>
double scalar_value(const T& x) {
    return scalar_value(x.value());
}

}  // namespace tvid

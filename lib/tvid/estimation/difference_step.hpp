#pragma once
// The central-difference step for a parameter at x with bounds [lower, upper]: ε^(1/3) of
// its magnitude (of a thousandth of the bound width, or 1, when it is zero), which
// balances truncation against rounding error. For every Jacobian column formed by
// differences (experiment_least_squares.cpp, forward_sensitivity.cpp).

#include <cmath>

namespace tvid {

inline double difference_step(double x, double lower, double upper) {
    double scale = std::abs(x);
    if (scale == 0.0) scale = std::isfinite(upper - lower) && upper - lower < 1e100 ? 1e-3 * (upper - lower) : 1.0;
    return 6e-6 * scale;
}

}  // namespace tvid

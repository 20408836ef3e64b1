#pragma once
// The one central-difference step rule for a free parameter's Jacobian column, wherever a
// column is formed by differences (ResidualEvaluator's `jacobian: fd` and input-delay
// columns, `tvid sensitivity`'s input-delay traces), chosen by the parameter's kind:
//  - a model quantity, gain or offset: ε^(1/3) (≈ 6e-6, which balances truncation against
//    rounding) of its magnitude, but never of less than a thousandth of its bound width
//    (1 when unbounded), so that a parameter at or near 0 (an offset, a phase) still gets a
//    step that moves the residuals;
//  - a channel's delay: a thousandth of the recording's sample period, whatever its value
//    or bounds (the interpolation between samples is what the step must resolve).

#include <algorithm>
#include <cmath>

namespace tvid {

/// The step of a model quantity, gain or offset at x with bounds [lower, upper].
inline double difference_step(double x, double lower, double upper) {
    const double width = upper - lower;
    double scale = std::abs(x);
    if (std::isfinite(width) && width < 1e100) scale = std::max(scale, 1e-3 * width);
    if (scale == 0.0) scale = 1.0;
    return 6e-6 * scale;
}

/// The step of a channel delay on a recording sampled every `sample_period` seconds.
inline double delay_difference_step(double sample_period) { return 1e-3 * sample_period; }

}  // namespace tvid

#pragma once
// The edge of the classical RK4 method's stability region: a linear mode of eigenvalue λ
// simulated at step h stays bounded while |1 + z + z²/2 + z³/6 + z⁴/24| ≤ 1, z = λh. Along
// the negative real axis the region ends at |z| = 2.785, along the imaginary at 2.828.

#include <complex>

namespace tvid {

/// The edge of RK4's stability region along direction `angle` (radians, π = the negative
/// real axis); directions in the right half-plane count as the imaginary axis.
double rk4_stability_radius(double angle);

/// A lower bound of rk4_stability_radius over every direction: the edge is nearest the
/// origin at about 2.6156, near 123° (tests/unit/test_fit_verdict.cpp scans it). A mode with
/// |λh| below kStableMargin times this bound is within the margin whatever its direction,
/// which spares the edge's search for the common candidate far from stiff.
inline constexpr double kRk4RadiusLowerBound = 2.6;

/// |λh| over the edge in λ's direction: below 1 the mode is simulated stably at step h.
inline double rk4_margin(std::complex<double> lambda, double h) {
    const double rate = std::abs(lambda);
    return rate > 0.0 ? rate * h / rk4_stability_radius(std::arg(lambda)) : 0.0;
}

}  // namespace tvid

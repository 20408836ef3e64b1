#include "tvid/sim/rk4_stability.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace tvid {

namespace {

double rk4_amplification(std::complex<double> z) {
    return std::abs(1.0 + z * (1.0 + z * (0.5 + z * (1.0 / 6.0 + z / 24.0))));
}

}  // namespace

double rk4_stability_radius(double angle) {
    const double phi = std::clamp(std::abs(angle), std::numbers::pi / 2, std::numbers::pi);
    const std::complex<double> direction = std::polar(1.0, phi);
    // The region is star-shaped about 0 in the left half-plane: scan out to the first
    // r where the amplification exceeds 1, then bisect.
    double inside = 0.0, outside = 0.0;
    for (double r = 0.05; r <= 4.0; r += 0.05) {
        if (rk4_amplification(r * direction) > 1.0) { outside = r; break; }
        inside = r;
    }
    if (outside == 0.0) return 4.0;
    for (int i = 0; i < 60; ++i) {
        const double mid = 0.5 * (inside + outside);
        (rk4_amplification(mid * direction) > 1.0 ? outside : inside) = mid;
    }
    return inside;
}

}  // namespace tvid

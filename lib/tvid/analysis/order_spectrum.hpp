#pragma once
// Order spectrum of an engine signal: its content at multiples of the crankshaft's
// rotation, cycle by cycle. Each complete engine cycle of the samples is resampled onto M
// uniform crank-angle points θ_j = j·Θ/M (Θ the cycle, 720° four-stroke), linear in angle
// between samples, and its discrete Fourier transform X_m = Σ_j x_j e^{−2πi m j/M} read at
// m = 1 … m_max. Bin m is order o = m / R, R the revolutions per cycle (2 four-stroke), so
//   x(θ) = mean + Σ_o A_o cos(o·θ + φ_o),   A_o = 2 |X_m| / M,   φ_o = arg X_m,
// θ the crank angle in radians from the cycle's start. A signal recorded against time at a
// varying speed becomes periodic in angle, which a time spectrum smears.

#include <cstddef>
#include <span>
#include <vector>

namespace tvid {

struct OrderSettings {
    double max_order = 12.0;      ///< orders 1/R, 2/R, … up to this
    double cycle_deg = 720.0;     ///< crank angle of one engine cycle (720 four-stroke, 360 two-stroke)
    std::size_t grid_points = 0;  ///< M; 0: the samples per cycle (Θ over the median spacing), at least 2·m_max + 2
};

struct CycleOrderSpectrum {
    long long cycle = 0;            ///< cycle k starts at origin + k·Θ
    double start_deg = 0.0;         ///< its start angle
    std::vector<double> order;      ///< o = m / R
    std::vector<double> amplitude;  ///< A_o, in the signal's unit
    std::vector<double> phase_deg;  ///< φ_o in degrees, (−180, 180]
    double mean = 0.0;              ///< of the resampled cycle
    double variance = 0.0;          ///< of the resampled cycle about its mean: Σ_o A_o²/2 when band-limited
};

/// Every complete cycle that `angle_deg` (cumulative crank angle per sample, increasing)
/// covers: the grid of cycle k, origin_deg + k·Θ + j·Θ/M for j = 0 … M−1, may reach at most
/// one sample spacing beyond the first or last sample (a window that ends on the next
/// cycle's first sample, or begins one sample after its cycle's start), where the end value
/// is held. `x` has the length of `angle_deg`; non-finite values in a cycle skip the cycle.
std::vector<CycleOrderSpectrum> order_spectrum(std::span<const double> angle_deg, std::span<const double> x,
                                               double origin_deg, const OrderSettings& settings = {});

}  // namespace tvid

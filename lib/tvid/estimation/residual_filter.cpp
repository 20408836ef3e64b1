#include "tvid/estimation/residual_filter.hpp"

#include <cmath>
#include <numbers>

namespace tvid {

namespace {

// The second-order Butterworth high-pass at fc for sample interval dt, by the bilinear
// transform with the cut-off prewarped: H(s) = s² / (s² + √2 ωc s + ωc²).
struct Biquad {
    double b0, b1, b2, a1, a2;
};

Biquad butterworth_highpass(double fc, double dt) {
    const double k = std::tan(std::numbers::pi * fc * dt);
    const double norm = 1.0 / (1.0 + std::numbers::sqrt2 * k + k * k);
    return Biquad{norm, -2.0 * norm, norm, 2.0 * (k * k - 1.0) * norm, (1.0 - std::numbers::sqrt2 * k + k * k) * norm};
}

// One pass of the biquad over the strided sequence, forward (step +1) or backward.
void run(const Biquad& q, double* r, std::size_t n, std::size_t stride, bool forward) {
    double x1 = 0, x2 = 0, y1 = 0, y2 = 0;
    for (std::size_t j = 0; j < n; ++j) {
        double& v = r[(forward ? j : n - 1 - j) * stride];
        const double x = v;
        const double y = q.b0 * x + q.b1 * x1 + q.b2 * x2 - q.a1 * y1 - q.a2 * y2;
        x2 = x1, x1 = x, y2 = y1, y1 = y;
        v = y;
    }
}

}  // namespace

void filter_residuals(const ScoringFilter& f, const double* t, double* r, std::size_t n, std::size_t stride) {
    if (n == 0 || !f.active()) return;
    const auto at = [&](std::size_t i) -> double& { return r[i * stride]; };
    const double count = static_cast<double>(n);
    if (f.detrend == Detrend::mean || (f.detrend == Detrend::linear && n == 1)) {
        double mean = 0.0;
        for (std::size_t i = 0; i < n; ++i) mean += at(i);
        mean /= count;
        for (std::size_t i = 0; i < n; ++i) at(i) -= mean;
    } else if (f.detrend == Detrend::linear) {
        // The least-squares line r̄ + b·(t − t̄).
        double t_mean = 0.0, r_mean = 0.0;
        for (std::size_t i = 0; i < n; ++i) t_mean += t[i], r_mean += at(i);
        t_mean /= count, r_mean /= count;
        double stt = 0.0, str = 0.0;
        for (std::size_t i = 0; i < n; ++i) {
            stt += (t[i] - t_mean) * (t[i] - t_mean);
            str += (t[i] - t_mean) * (at(i) - r_mean);
        }
        const double b = stt > 0 ? str / stt : 0.0;
        for (std::size_t i = 0; i < n; ++i) at(i) -= r_mean + b * (t[i] - t_mean);
    }
    if (f.highpass > 0 && n >= 2) {
        const double dt = (t[n - 1] - t[0]) / (count - 1.0);
        const Biquad q = butterworth_highpass(f.highpass, dt);
        run(q, r, n, stride, true);
        run(q, r, n, stride, false);
    }
}

}  // namespace tvid

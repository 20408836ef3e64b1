#include "tvid/analysis/order_spectrum.hpp"

#include <algorithm>
#include <cmath>
#include <complex>
#include <numbers>

namespace tvid {

namespace {

double median_spacing(std::span<const double> angle) {
    std::vector<double> d(angle.size() - 1);
    for (std::size_t i = 0; i + 1 < angle.size(); ++i) d[i] = angle[i + 1] - angle[i];
    std::nth_element(d.begin(), d.begin() + static_cast<std::ptrdiff_t>(d.size() / 2), d.end());
    return d[d.size() / 2];
}

// x at angle a, linear between samples, the end value held beyond them; `cursor` moves forward.
double value_at_angle(std::span<const double> angle, std::span<const double> x, double a, std::size_t& cursor) {
    if (a <= angle.front()) return x.front();
    if (a >= angle.back()) return x.back();
    while (cursor + 2 < angle.size() && angle[cursor + 1] <= a) ++cursor;
    const double t = (a - angle[cursor]) / (angle[cursor + 1] - angle[cursor]);
    return x[cursor] + t * (x[cursor + 1] - x[cursor]);
}

}  // namespace

std::vector<CycleOrderSpectrum> order_spectrum(std::span<const double> angle_deg, std::span<const double> x,
                                               double origin_deg, const OrderSettings& settings) {
    std::vector<CycleOrderSpectrum> out;
    if (angle_deg.size() < 2 || x.size() != angle_deg.size() || !(settings.cycle_deg > 0) ||
        !(settings.max_order > 0))
        return out;
    const double cycle = settings.cycle_deg;
    const double revolutions = cycle / 360.0;  // R
    const auto top_bin = static_cast<std::size_t>(std::floor(settings.max_order * revolutions + 1e-9));
    if (top_bin == 0) return out;
    const double spacing = median_spacing(angle_deg);
    if (!(spacing > 0)) return out;
    std::size_t m = settings.grid_points;
    if (m == 0) m = static_cast<std::size_t>(std::lround(cycle / spacing));
    m = std::max(m, 2 * top_bin + 2);
    // e^{−2πi j/M}: the DFT's twiddles, indexed (m·j) mod M.
    std::vector<std::complex<double>> twiddle(m);
    for (std::size_t j = 0; j < m; ++j)
        twiddle[j] = std::polar(1.0, -2.0 * std::numbers::pi * static_cast<double>(j) / static_cast<double>(m));

    const double step = cycle / static_cast<double>(m);
    const auto first = static_cast<long long>(std::ceil((angle_deg.front() - spacing - origin_deg) / cycle - 1e-12));
    std::vector<double> grid(m);
    std::size_t cursor = 0;
    for (long long k = first;; ++k) {
        const double start = origin_deg + static_cast<double>(k) * cycle;
        if (start + static_cast<double>(m - 1) * step > angle_deg.back() + spacing + 1e-9 * cycle) break;
        if (start < angle_deg.front() - spacing - 1e-9 * cycle) continue;
        bool finite = true;
        double mean = 0.0;
        for (std::size_t j = 0; j < m; ++j) {
            grid[j] = value_at_angle(angle_deg, x, start + static_cast<double>(j) * step, cursor);
            finite = finite && std::isfinite(grid[j]);
            mean += grid[j];
        }
        if (!finite) continue;
        mean /= static_cast<double>(m);
        CycleOrderSpectrum c;
        c.cycle = k;
        c.start_deg = start;
        c.mean = mean;
        for (double v : grid) c.variance += (v - mean) * (v - mean);
        c.variance /= static_cast<double>(m);
        for (std::size_t bin = 1; bin <= top_bin; ++bin) {
            std::complex<double> sum = 0.0;
            for (std::size_t j = 0; j < m; ++j) sum += grid[j] * twiddle[(bin * j) % m];
            c.order.push_back(static_cast<double>(bin) / revolutions);
            c.amplitude.push_back(2.0 * std::abs(sum) / static_cast<double>(m));
            c.phase_deg.push_back(std::arg(sum) * 180.0 / std::numbers::pi);
        }
        out.push_back(std::move(c));
    }
    return out;
}

}  // namespace tvid

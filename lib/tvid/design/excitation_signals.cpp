#include "tvid/design/excitation_signals.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <numbers>

namespace tvid {

std::vector<double> excitation_time_grid(std::size_t samples, double sample_rate) {
    std::vector<double> t(samples);
    for (std::size_t k = 0; k < samples; ++k) t[k] = static_cast<double>(k) / sample_rate;
    return t;
}

std::vector<double> chirp_shape(const std::vector<double>& time, double f_low, double f_high) {
    std::vector<double> s(time.size(), 0.0);
    if (time.empty()) return s;
    const double T = time.back() - time.front();
    for (std::size_t k = 0; k < time.size(); ++k) {
        const double t = time[k] - time.front();
        const double sweep = T > 0 ? (f_high - f_low) * t * t / (2 * T) : 0.0;
        s[k] = std::sin(2 * std::numbers::pi * (f_low * t + sweep));
    }
    return s;
}

namespace {
// Feedback taps (1-based bit positions) of maximum-length Fibonacci LFSRs, orders 3..24
// (Xilinx XAPP 052, table 3).
struct Taps {
    int order;
    int taps[4];
};
constexpr Taps kTaps[] = {
    {3, {3, 2, 0, 0}},     {4, {4, 3, 0, 0}},     {5, {5, 3, 0, 0}},      {6, {6, 5, 0, 0}},
    {7, {7, 6, 0, 0}},     {8, {8, 6, 5, 4}},     {9, {9, 5, 0, 0}},      {10, {10, 7, 0, 0}},
    {11, {11, 9, 0, 0}},   {12, {12, 6, 4, 1}},   {13, {13, 4, 3, 1}},    {14, {14, 5, 3, 1}},
    {15, {15, 14, 0, 0}},  {16, {16, 15, 13, 4}}, {17, {17, 14, 0, 0}},   {18, {18, 11, 0, 0}},
    {19, {19, 6, 2, 1}},   {20, {20, 17, 0, 0}},  {21, {21, 19, 0, 0}},   {22, {22, 21, 0, 0}},
    {23, {23, 18, 0, 0}},  {24, {24, 23, 22, 17}},
};
}  // namespace

std::vector<double> prbs_shape(std::size_t samples, double sample_rate, double f_high) {
    const auto per_bit = static_cast<std::size_t>(std::max(1.0, std::round(sample_rate / (2 * f_high))));
    const std::size_t bits = (samples + per_bit - 1) / per_bit;
    const Taps* taps = &kTaps[std::size(kTaps) - 1];
    for (const Taps& t : kTaps)
        if ((std::uint64_t{1} << t.order) - 1 >= bits) {
            taps = &t;
            break;
        }
    std::uint32_t reg = (std::uint32_t{1} << taps->order) - 1;  // all ones
    std::vector<double> s(samples);
    for (std::size_t b = 0, k = 0; k < samples; ++b) {
        const double level = (reg & 1u) ? 1.0 : -1.0;
        for (std::size_t i = 0; i < per_bit && k < samples; ++i) s[k++] = level;
        std::uint32_t feedback = 0;
        for (int tap : taps->taps)
            if (tap > 0) feedback ^= (reg >> (taps->order - tap)) & 1u;
        reg = (reg >> 1) | (feedback << (taps->order - 1));
    }
    return s;
}

std::vector<double> schroeder_multisine_shape(const std::vector<double>& time, double sample_rate, double f_low,
                                              double f_high) {
    std::vector<double> s(time.size(), 0.0);
    const double T = static_cast<double>(time.size()) / sample_rate;  // one period of the grid's frequencies
    const auto first = static_cast<long>(std::max(1.0, std::ceil(f_low * T - 1e-9)));
    const auto last = static_cast<long>(std::floor(f_high * T + 1e-9));
    const long K = last - first + 1;
    for (long k = first; k <= last; ++k) {
        const auto j = static_cast<double>(k - first + 1);
        const double phase = -std::numbers::pi * j * (j - 1) / static_cast<double>(K);
        const double w = 2 * std::numbers::pi * static_cast<double>(k) / T;
        for (std::size_t i = 0; i < time.size(); ++i) s[i] += std::cos(w * (time[i] - time.front()) + phase);
    }
    return s;
}

double rms_about(const std::vector<double>& v, double base) {
    if (v.empty()) return 0.0;
    double sum = 0.0;
    for (double x : v) sum += (x - base) * (x - base);
    return std::sqrt(sum / static_cast<double>(v.size()));
}

namespace {
std::vector<double> clipped(const std::vector<double>& shape, double gain, double base, double low, double high) {
    std::vector<double> v(shape.size());
    for (std::size_t k = 0; k < shape.size(); ++k) v[k] = std::clamp(base + gain * shape[k], low, high);
    return v;
}
}  // namespace

std::optional<std::vector<double>> scaled_excitation(const std::vector<double>& shape, double base, double rms,
                                                     double low, double high, double* reachable) {
    // The limit of an infinite gain: every sample at the limit on its side.
    double sum = 0.0;
    for (double s : shape) {
        const double d = s > 0 ? high - base : (s < 0 ? low - base : 0.0);
        sum += d * d;
    }
    const double largest = shape.empty() ? 0.0 : std::sqrt(sum / static_cast<double>(shape.size()));
    if (reachable) *reachable = largest;
    if (!(rms < largest * (1 - 1e-9))) return std::nullopt;
    const double shape_rms = rms_about(shape, 0.0);
    double lo = 0.0, hi = rms / shape_rms;  // unclipped, this gain meets the RMS; clipping needs more
    while (rms_about(clipped(shape, hi, base, low, high), base) < rms) hi *= 2;
    for (int i = 0; i < 100 && hi - lo > 1e-14 * hi; ++i) {
        const double mid = 0.5 * (lo + hi);
        (rms_about(clipped(shape, mid, base, low, high), base) < rms ? lo : hi) = mid;
    }
    return clipped(shape, hi, base, low, high);
}

}  // namespace tvid

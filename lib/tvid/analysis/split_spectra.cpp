#include "tvid/analysis/split_spectra.hpp"

#include <algorithm>
#include <cmath>
#include <map>
#include <numbers>
#include <span>

#include "tvid/analysis/welch_spectrum.hpp"

namespace tvid {

namespace {

// A contiguous run of samples of one window in which every output's measured and
// simulated values are finite.
struct SpectrumStretch {
    const WindowTrace* trace = nullptr;
    std::size_t begin = 0, end = 0;
    std::size_t size() const { return end - begin; }
};

// The median time step of one window's scored samples: a longer step than kGapStepFactor
// times it is a gap in the recording. Each window by its own: recordings of several rates
// may be read in one experiment.
double median_step(const std::vector<double>& t) {
    std::vector<double> steps;
    for (std::size_t i = 0; i + 1 < t.size(); ++i) steps.push_back(t[i + 1] - t[i]);
    if (steps.empty()) return 0.0;
    const auto middle = steps.begin() + static_cast<std::ptrdiff_t>(steps.size() / 2);
    std::nth_element(steps.begin(), middle, steps.end());
    return *middle;
}

std::vector<SpectrumStretch> finite_stretches(const SplitEvaluation& split, std::size_t outputs, std::size_t& gaps) {
    std::vector<SpectrumStretch> stretches;
    gaps = 0;
    for (const WindowEvaluation& w : split.windows) {
        const WindowTrace& tr = w.trace;
        if (tr.status != SimulationStatus::ok || tr.measured.size() < outputs || tr.simulated.size() < outputs) continue;
        const auto records = gap_free_records(tr.time, median_step(tr.time));
        gaps += records.size() - 1;
        for (const auto& [from, to] : records) {
            std::size_t begin = from;
            for (std::size_t i = from; i <= to; ++i) {
                bool finite = i < to;
                for (std::size_t k = 0; finite && k < outputs; ++k)
                    finite = std::isfinite(tr.measured[k][i]) && std::isfinite(tr.simulated[k][i]);
                if (finite) continue;
                if (i > begin + 1) stretches.push_back({&tr, begin, i});
                begin = i + 1;
            }
        }
    }
    return stretches;
}

// A stretch's sample rate [Hz]: its (samples − 1) over its span.
double stretch_rate(const SpectrumStretch& s) {
    const double span = s.trace->time[s.end - 1] - s.trace->time[s.begin];
    return span > 0 ? static_cast<double>(s.size() - 1) / span : 0.0;
}

// The stretches at one sample rate, that of most samples: a spectrum averages segments on
// one frequency grid, and a stretch at another rate would put its lines at the wrong
// frequencies. The others are counted in `left_out` (samples) at `left_out_hz`.
std::vector<SpectrumStretch> one_rate(const std::vector<SpectrumStretch>& stretches, std::size_t& left_out,
                                      double& left_out_hz) {
    constexpr double kSameRate = 1e-3;  // relative: a logger's clock jitters
    const auto same = [&](double a, double b) { return std::abs(a - b) <= kSameRate * std::max(a, b); };
    double best_rate = 0.0;
    std::size_t best = 0;
    for (const SpectrumStretch& s : stretches) {
        std::size_t samples = 0;
        for (const SpectrumStretch& o : stretches)
            if (same(stretch_rate(o), stretch_rate(s))) samples += o.size();
        if (samples > best) best = samples, best_rate = stretch_rate(s);
    }
    std::vector<SpectrumStretch> kept;
    left_out = 0;
    for (const SpectrumStretch& s : stretches) {
        if (same(stretch_rate(s), best_rate)) {
            kept.push_back(s);
        } else {
            left_out += s.size();
            left_out_hz = stretch_rate(s);
        }
    }
    return kept;
}

void accumulate(std::vector<double>& sum, const Spectrum& s) {
    if (sum.empty()) sum.assign(s.density.size(), 0.0);
    for (std::size_t k = 0; k < sum.size(); ++k) sum[k] += s.density[k] * static_cast<double>(s.segments);
}

}  // namespace

SplitSpectra split_spectra(const SplitEvaluation& split, std::size_t outputs) {
    SplitSpectra out;
    out.split = split.split;
    const std::vector<SpectrumStretch> stretches =
        one_rate(finite_stretches(split, outputs, out.gaps), out.other_rate_samples, out.other_rate_hz);
    std::size_t total = 0, longest = 0;
    double span = 0.0;
    for (const SpectrumStretch& s : stretches) {
        total += s.size();
        longest = std::max(longest, s.size());
        span += s.trace->time[s.end - 1] - s.trace->time[s.begin];
    }
    if (longest < 2 || !(span > 0)) return out;
    const double fs = static_cast<double>(total - stretches.size()) / span;
    std::size_t length = welch_segment_length(total);
    while (length > longest) length = length / 2 >= 64 ? length / 2 : longest;
    const WelchSettings settings{length, 0.5};

    out.outputs.assign(outputs, {});
    std::vector<double> residual;
    for (const SpectrumStretch& s : stretches) {
        if (s.size() < length) continue;
        out.samples += s.size();
        for (std::size_t k = 0; k < outputs; ++k) {
            const std::span<const double> y(s.trace->measured[k].data() + s.begin, s.size());
            const std::span<const double> ys(s.trace->simulated[k].data() + s.begin, s.size());
            residual.resize(s.size());
            for (std::size_t i = 0; i < s.size(); ++i) residual[i] = y[i] - ys[i];
            const Spectrum measured = welch_psd(y, fs, settings);
            accumulate(out.outputs[k].measured, measured);
            accumulate(out.outputs[k].simulated, welch_psd(ys, fs, settings));
            accumulate(out.outputs[k].residual, welch_psd(residual, fs, settings));
            if (k == 0) {
                out.segments += measured.segments;
                if (out.frequency_hz.empty()) out.frequency_hz = measured.frequency_hz;
            }
        }
    }
    if (out.segments == 0) {
        out.outputs.clear();
        return out;
    }
    out.sample_rate_hz = fs;
    out.segment_length = length;
    out.resolution_hz = fs / static_cast<double>(length);
    for (OutputSpectra& o : out.outputs)
        for (std::vector<double>* d : {&o.measured, &o.simulated, &o.residual})
            for (double& v : *d) v /= static_cast<double>(out.segments);
    return out;
}

SpectralPeak dominant_band(const std::vector<double>& frequency_hz, const std::vector<double>& density) {
    SpectralPeak p;
    if (frequency_hz.size() < 3 || density.size() != frequency_hz.size()) return p;
    const double df = frequency_hz[1] - frequency_hz[0];
    std::size_t peak = 1;
    for (std::size_t k = 1; k < density.size(); ++k) {
        p.variance += density[k] * df;
        if (density[k] > density[peak]) peak = k;
    }
    p.variance += density[0] * df;
    if (!(p.variance > 0) || !std::isfinite(p.variance)) return p;
    p.available = true;
    p.peak_hz = frequency_hz[peak];
    const double half_width = std::max(2 * df, 0.05 * p.peak_hz);
    p.band_low_hz = std::max(0.0, p.peak_hz - half_width);
    p.band_high_hz = std::min(frequency_hz.back(), p.peak_hz + half_width);
    double in_band = 0.0;
    for (std::size_t k = 0; k < density.size(); ++k)
        if (frequency_hz[k] >= p.band_low_hz - 1e-9 * df && frequency_hz[k] <= p.band_high_hz + 1e-9 * df)
            in_band += density[k] * df;
    p.share = in_band / p.variance;
    return p;
}

SplitOrders split_orders(const SplitEvaluation& split, std::size_t outputs, const std::vector<double>& crank_angle_rad,
                         const OrderSettings& settings, const std::vector<RowSpan>& recordings) {
    SplitOrders out;
    out.split = split.split;
    if (crank_angle_rad.empty()) return out;
    const double to_deg = 180.0 / std::numbers::pi;
    const double cycle_deg = settings.cycle_deg;
    // As experiment/window_reader.cpp counts cycles: from the first cycle start at or after
    // the first angle of the window's recording.
    const auto origin_of = [&](const WindowTrace& tr) {
        const std::size_t r = tr.window ? tr.window->recording : 0;
        const double first = r < recordings.size() ? crank_angle_rad[recordings[r].begin] : crank_angle_rad.front();
        return std::ceil(first * to_deg / cycle_deg - 1e-9) * cycle_deg;
    };
    std::vector<double> angle, residual;
    for (const WindowEvaluation& w : split.windows) {
        const WindowTrace& tr = w.trace;
        if (tr.status != SimulationStatus::ok || tr.measured.size() < outputs || tr.samples.size() < 2) continue;
        const double origin = origin_of(tr);
        angle.resize(tr.samples.size());
        bool inside = true;
        for (std::size_t i = 0; i < tr.samples.size(); ++i) {
            inside = inside && tr.samples[i] < crank_angle_rad.size();
            if (inside) angle[i] = crank_angle_rad[tr.samples[i]] * to_deg;
        }
        if (!inside) continue;
        // Per cycle (in order), the outputs' rows.
        std::map<long long, std::vector<CycleOrders>> by_cycle;
        for (std::size_t k = 0; k < outputs; ++k) {
            const std::vector<double>& y = tr.measured[k];
            const std::vector<double>& ys = tr.simulated[k];
            residual.resize(y.size());
            for (std::size_t i = 0; i < y.size(); ++i) residual[i] = y[i] - ys[i];
            const std::vector<CycleOrderSpectrum> m = order_spectrum(angle, y, origin, settings);
            const std::vector<CycleOrderSpectrum> s = order_spectrum(angle, ys, origin, settings);
            const std::vector<CycleOrderSpectrum> r = order_spectrum(angle, residual, origin, settings);
            // A cycle counts where all three are whole (a non-finite value skips it in one of them).
            for (const CycleOrderSpectrum& rc : r) {
                const auto same = [&](const CycleOrderSpectrum& c) { return c.cycle == rc.cycle; };
                const auto mi = std::find_if(m.begin(), m.end(), same);
                const auto si = std::find_if(s.begin(), s.end(), same);
                if (mi == m.end() || si == s.end()) continue;
                by_cycle[rc.cycle].push_back({k, tr.window ? tr.window->label : std::string(), *mi, *si, rc});
            }
        }
        for (auto& entry : by_cycle)
            for (CycleOrders& row : entry.second) out.cycles.push_back(std::move(row));
    }
    return out;
}

OrderPeak dominant_order(const SplitOrders& orders, std::size_t output) {
    OrderPeak p;
    std::vector<double> power;
    const CycleOrderSpectrum* first = nullptr;
    for (const CycleOrders& c : orders.cycles) {
        if (c.output != output) continue;
        if (!first) {
            first = &c.residual;
            power.assign(c.residual.amplitude.size(), 0.0);
        }
        if (c.residual.amplitude.size() != power.size()) continue;
        for (std::size_t i = 0; i < power.size(); ++i) power[i] += c.residual.amplitude[i] * c.residual.amplitude[i] / 2;
        p.variance += c.residual.variance;
        ++p.cycles;
    }
    if (p.cycles == 0 || power.empty() || !(p.variance > 0)) return p;
    const std::size_t best = static_cast<std::size_t>(std::max_element(power.begin(), power.end()) - power.begin());
    const double n = static_cast<double>(p.cycles);
    p.available = true;
    p.order = first->order[best];
    p.amplitude = std::sqrt(2 * power[best] / n);
    p.variance /= n;
    p.share = power[best] / n / p.variance;
    for (double w : power) p.orders_share += w / n / p.variance;
    p.max_order = first->order.back();
    return p;
}

}  // namespace tvid

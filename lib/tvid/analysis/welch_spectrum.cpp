#include "tvid/analysis/welch_spectrum.hpp"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <limits>
#include <numbers>
#include <stdexcept>
#include <unsupported/Eigen/FFT>

namespace tvid {

namespace {

// The segments' start indices and their common machinery: the Hann window, its power
// U = Σ w², and one FFT whose plan is reused for every segment.
class WelchSegmenter {
public:
    WelchSegmenter(std::size_t n, const WelchSettings& settings) : length_(welch_segment_length(n, settings)) {
        if (length_ < 2) return;
        const double overlap = std::clamp(std::isfinite(settings.overlap) ? settings.overlap : 0.5, 0.0, 0.95);
        hop_ = std::max<std::size_t>(1, static_cast<std::size_t>(std::lround(static_cast<double>(length_) * (1.0 - overlap))));
        count_ = 1 + (n - length_) / hop_;
        // Periodic Hann window: w_i = sin²(π i / L).
        window_.resize(length_);
        for (std::size_t i = 0; i < length_; ++i) {
            const double s = std::sin(std::numbers::pi * static_cast<double>(i) / static_cast<double>(length_));
            window_[i] = s * s;
            window_power_ += window_[i] * window_[i];
        }
        fft_.SetFlag(Eigen::FFT<double>::HalfSpectrum);
        buffer_.resize(length_);
    }

    std::size_t length() const { return length_; }
    std::size_t count() const { return count_; }
    std::size_t bins() const { return length_ / 2 + 1; }
    double window_power() const { return window_power_; }

    /// The DFT (bins 0 … L/2) of segment `s` of x: mean removed, Hann-windowed.
    void transform(std::span<const double> x, std::size_t s, std::vector<std::complex<double>>& out) {
        const std::size_t start = s * hop_;
        double mean = 0.0;
        for (std::size_t i = 0; i < length_; ++i) mean += x[start + i];
        mean /= static_cast<double>(length_);
        for (std::size_t i = 0; i < length_; ++i) buffer_[i] = (x[start + i] - mean) * window_[i];
        out.resize(bins());
        fft_.fwd(out.data(), buffer_.data(), static_cast<Eigen::Index>(length_));
    }

    std::vector<double> frequencies(double fs) const {
        std::vector<double> f(bins());
        for (std::size_t k = 0; k < f.size(); ++k) f[k] = static_cast<double>(k) * fs / static_cast<double>(length_);
        return f;
    }

    /// c_k / (fs · U): the one-sided density's scale at bin k.
    double density_scale(std::size_t k, double fs) const {
        const bool edge = k == 0 || (length_ % 2 == 0 && k == length_ / 2);
        return (edge ? 1.0 : 2.0) / (fs * window_power_);
    }

private:
    std::size_t length_ = 0;
    std::size_t hop_ = 1;
    std::size_t count_ = 0;
    std::vector<double> window_;
    double window_power_ = 0.0;
    Eigen::FFT<double> fft_;
    std::vector<double> buffer_;
};

bool valid_rate(double fs) { return std::isfinite(fs) && fs > 0.0; }

}  // namespace

std::size_t welch_segment_length(std::size_t n, const WelchSettings& settings) {
    if (settings.segment_length > 0) return std::min(settings.segment_length, n);
    if (n < 64) return n;
    std::size_t length = 64;
    while (length * 2 <= n / 8) length *= 2;
    return length;
}

double median_time_step(std::span<const double> time) {
    if (time.size() < 2) return 0.0;
    std::vector<double> steps(time.size() - 1);
    for (std::size_t i = 0; i + 1 < time.size(); ++i) steps[i] = time[i + 1] - time[i];
    const auto middle = steps.begin() + static_cast<std::ptrdiff_t>(steps.size() / 2);
    std::nth_element(steps.begin(), middle, steps.end());
    return *middle;
}

std::vector<std::pair<std::size_t, std::size_t>> gap_free_records(std::span<const double> time, double median_step) {
    std::vector<std::pair<std::size_t, std::size_t>> records;
    if (time.empty()) return records;
    const double gap = kGapStepFactor * median_step;
    std::size_t begin = 0;
    for (std::size_t i = 1; i < time.size(); ++i)
        if (median_step > 0.0 && time[i] - time[i - 1] > gap) {
            records.emplace_back(begin, i);
            begin = i;
        }
    records.emplace_back(begin, time.size());
    return records;
}

Spectrum welch_psd(std::span<const double> x, double sample_rate_hz, const WelchSettings& settings) {
    Spectrum result;
    if (x.size() < 2 || !valid_rate(sample_rate_hz)) return result;
    WelchSegmenter segmenter(x.size(), settings);
    if (segmenter.length() < 2) return result;
    result.frequency_hz = segmenter.frequencies(sample_rate_hz);
    result.density.assign(segmenter.bins(), 0.0);
    std::vector<std::complex<double>> spectrum;
    for (std::size_t s = 0; s < segmenter.count(); ++s) {
        segmenter.transform(x, s, spectrum);
        for (std::size_t k = 0; k < spectrum.size(); ++k) result.density[k] += std::norm(spectrum[k]);
    }
    const double segments = static_cast<double>(segmenter.count());
    for (std::size_t k = 0; k < result.density.size(); ++k)
        result.density[k] *= segmenter.density_scale(k, sample_rate_hz) / segments;
    result.segments = segmenter.count();
    return result;
}

FrfEstimate estimate_frf_h1(std::span<const double> input, std::span<const double> output, double sample_rate_hz,
                            const WelchSettings& settings) {
    const std::span<const double> inputs[] = {input}, outputs[] = {output};
    WelchSettings one = settings;
    one.segment_length = welch_segment_length(input.size(), settings);
    return estimate_frf_h1(std::span<const std::span<const double>>(inputs),
                           std::span<const std::span<const double>>(outputs), sample_rate_hz, one);
}

FrfEstimate estimate_frf_h1(std::span<const std::span<const double>> inputs,
                            std::span<const std::span<const double>> outputs, double sample_rate_hz,
                            const WelchSettings& settings) {
    if (inputs.size() != outputs.size())
        throw std::invalid_argument("estimate_frf_h1: as many input records as output records");
    for (std::size_t r = 0; r < inputs.size(); ++r)
        if (inputs[r].size() != outputs[r].size())
            throw std::invalid_argument("estimate_frf_h1: input and output differ in length");
    FrfEstimate result;
    if (!valid_rate(sample_rate_hz) || settings.segment_length < 2) return result;
    const std::size_t length = settings.segment_length, bins = length / 2 + 1;
    std::vector<double> sxx(bins, 0.0), syy(bins, 0.0);
    std::vector<std::complex<double>> sxy(bins, 0.0), x_k, y_k;
    for (std::size_t r = 0; r < inputs.size(); ++r) {
        if (inputs[r].size() < length) continue;  // no segment fits: it would change the grid
        WelchSegmenter segmenter(inputs[r].size(), settings);
        for (std::size_t s = 0; s < segmenter.count(); ++s) {
            segmenter.transform(inputs[r], s, x_k);
            segmenter.transform(outputs[r], s, y_k);
            for (std::size_t k = 0; k < bins; ++k) {
                sxx[k] += std::norm(x_k[k]);
                syy[k] += std::norm(y_k[k]);
                sxy[k] += std::conj(x_k[k]) * y_k[k];
            }
        }
        result.segments += segmenter.count();
        if (result.frequency_hz.empty()) result.frequency_hz = segmenter.frequencies(sample_rate_hz);
    }
    if (result.segments == 0) return result;
    result.h1.resize(bins);
    result.coherence.resize(bins);
    for (std::size_t k = 0; k < bins; ++k) {
        result.h1[k] = sxx[k] > 0.0 ? sxy[k] / sxx[k] : std::complex<double>(0.0, 0.0);
        const double denominator = sxx[k] * syy[k];
        result.coherence[k] = result.segments < 2   ? std::numeric_limits<double>::quiet_NaN()
                              : denominator > 0.0 ? std::min(1.0, std::norm(sxy[k]) / denominator)
                                                  : 0.0;
    }
    return result;
}

}  // namespace tvid

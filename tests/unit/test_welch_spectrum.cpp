// Welch's power spectral density and the H1 frequency response against analytic values:
// a sine's power A²/2, white noise's flat level 2σ²/fs, and a first-order filter's
// response b / (1 − a e^{−jω}) within the standard error its coherence predicts.
#include <catch2/catch.hpp>
#include <algorithm>
#include <cmath>
#include <complex>
#include <numbers>
#include <random>
#include <span>
#include <vector>

#include "tvid/analysis/welch_spectrum.hpp"

namespace TVID_UNITY_ID {  // unique to this file in a unity build (tests/CMakeLists.txt)

using namespace tvid;

namespace {

// Σ P_k Δf over the bins within `half_width` bins of the largest one.
double power_around_peak(const Spectrum& s, std::size_t half_width) {
    std::size_t peak = 0;
    for (std::size_t k = 1; k < s.density.size(); ++k)
        if (s.density[k] > s.density[peak]) peak = k;
    const double df = s.frequency_hz[1] - s.frequency_hz[0];
    double sum = 0.0;
    for (std::size_t k = peak >= half_width ? peak - half_width : 0; k <= peak + half_width && k < s.density.size(); ++k)
        sum += s.density[k] * df;
    return sum;
}

}  // namespace

TEST_CASE("a sine of amplitude A has the power A squared over 2 around its frequency", "[spectra]") {
    const double fs = 1000.0, amplitude = 3.0, frequency = 54.3;  // not on a bin: the Hann window's leakage counts
    std::vector<double> x(16384);
    for (std::size_t i = 0; i < x.size(); ++i)
        x[i] = 0.7 + amplitude * std::sin(2 * std::numbers::pi * frequency * static_cast<double>(i) / fs + 0.4);
    const Spectrum s = welch_psd(x, fs);
    // Default segment: the largest power of two ≤ n/8 = 2048; 50 % overlap gives 15 segments.
    REQUIRE(s.frequency_hz.size() == 2048 / 2 + 1);
    CHECK(s.segments == 15);
    CHECK(s.frequency_hz[1] == Approx(fs / 2048));
    CHECK(power_around_peak(s, 6) == Approx(amplitude * amplitude / 2).epsilon(0.005));
    // The mean (0.7) is removed per segment: at 0 Hz only the window's leakage of the sine,
    // far below its peak.
    double peak = 0.0;
    for (double p : s.density) peak = std::max(peak, p);
    CHECK(s.density[0] < 1e-5 * peak);
    // Parseval: the whole density integrates to the variance A²/2.
    double total = 0.0;
    for (double p : s.density) total += p * fs / 2048;
    CHECK(total == Approx(amplitude * amplitude / 2).epsilon(0.005));
}

TEST_CASE("white noise of variance sigma squared has the flat density 2 sigma squared over fs", "[spectra]") {
    const double fs = 500.0, sigma = 2.0;
    std::mt19937 random(11);
    std::normal_distribution<double> gauss(0.0, sigma);
    std::vector<double> x(65536);
    for (double& v : x) v = gauss(random);
    const Spectrum s = welch_psd(x, fs, WelchSettings{256, 0.5});
    CHECK(s.segments == 511);
    const double level = 2 * sigma * sigma / fs;
    // Each bin averages 511 periodograms (χ² with ≈ 2·511/1.06 degrees of freedom for 50 %
    // overlapping Hann segments): a relative standard error of about 4.5 %. Every interior
    // bin lies within 6 of those; the mean over 127 bins within 1.5 %.
    double mean = 0.0;
    for (std::size_t k = 1; k + 1 < s.density.size(); ++k) {
        CHECK(std::abs(s.density[k] / level - 1.0) < 0.27);
        mean += s.density[k];
    }
    mean /= static_cast<double>(s.density.size() - 2);
    CHECK(mean == Approx(level).epsilon(0.015));
    // The Nyquist bin is not doubled: one-sided density holds only its one side.
    CHECK(s.density.back() == Approx(level).epsilon(0.5));
}

TEST_CASE("H1 of a first-order filter matches its analytic response within the coherence's standard error", "[spectra]") {
    // y[n] = a y[n−1] + b x[n]: H(e^{jω}) = b / (1 − a e^{−jω}), ω = 2π f / fs.
    const double fs = 200.0, a = 0.8, b = 0.5;
    std::mt19937 random(5);
    std::normal_distribution<double> gauss(0.0, 1.0);
    std::vector<double> x(40000), y(x.size()), y_noisy(x.size());
    double state = 0.0;
    for (std::size_t i = 0; i < x.size(); ++i) {
        x[i] = gauss(random);
        state = a * state + b * x[i];
        y[i] = state;
        y_noisy[i] = state + 0.6 * gauss(random);  // output noise: coherence between ≈ 0.1 and 0.9
    }
    const auto analytic = [&](double f) {
        const double omega = 2 * std::numbers::pi * f / fs;
        return b / (1.0 - a * std::exp(std::complex<double>(0.0, -omega)));
    };
    const WelchSettings settings{256, 0.5};

    SECTION("without noise the coherence is 1 and H1 the response") {
        const FrfEstimate frf = estimate_frf_h1(x, y, fs, settings);
        REQUIRE(frf.h1.size() == 129);
        // From bin 2 on: bins 0 and 1 share the segment's mean, which is removed.
        for (std::size_t k = 2; k < frf.h1.size(); ++k) {
            CHECK(frf.coherence[k] > 0.99);
            CHECK(std::abs(frf.h1[k] - analytic(frf.frequency_hz[k])) < 0.02 * std::abs(analytic(frf.frequency_hz[k])));
        }
    }
    SECTION("with output noise H1 stays unbiased, within its standard error") {
        const FrfEstimate frf = estimate_frf_h1(x, y_noisy, fs, settings);
        // Overlapping Hann segments are not independent: n_d ≈ segments / 1.06.
        const double nd = static_cast<double>(frf.segments) / 1.06;
        double worst_normalised = 0.0;
        for (std::size_t k = 2; k < frf.h1.size(); ++k) {
            const std::complex<double> h = analytic(frf.frequency_hz[k]);
            // The coherence the noise leaves: |H|² σx² / (|H|² σx² + σv²).
            const double expected_coherence = std::norm(h) / (std::norm(h) + 0.36);
            // Its estimate's standard error: sqrt(2 γ² (1 − γ²)² / n_d) (Bendat & Piersol).
            const double coherence_error =
                std::sqrt(2 * expected_coherence * std::pow(1 - expected_coherence, 2) / nd);
            CHECK(std::abs(frf.coherence[k] - expected_coherence) < 4.5 * coherence_error);
            const double g2 = frf.coherence[k];
            const double standard_error = std::sqrt((1 - g2) / (2 * nd * g2)) * std::abs(h);
            const double deviation = std::abs(std::abs(frf.h1[k]) - std::abs(h));
            CHECK(deviation < 4.5 * standard_error);
            // The phase's standard error is the same figure in radians over |H|.
            CHECK(std::abs(std::arg(frf.h1[k] / h)) < 4.5 * standard_error / std::abs(h));
            worst_normalised = std::max(worst_normalised, deviation / standard_error);
        }
        // And not a bound so loose it never bites: the worst of 128 bins is a few errors out.
        CHECK(worst_normalised > 1.0);
    }
}

TEST_CASE("a segment longer than the signal is the signal, mismatched lengths are refused", "[spectra]") {
    std::vector<double> x(100, 1.0), y(99, 1.0);
    CHECK(welch_segment_length(100) == 64);
    CHECK(welch_segment_length(40) == 40);
    CHECK(welch_segment_length(100000) == 8192);
    CHECK(welch_segment_length(100, WelchSettings{500, 0.5}) == 100);
    const Spectrum s = welch_psd(x, 10.0, WelchSettings{500, 0.5});
    CHECK(s.segments == 1);
    CHECK(s.density.size() == 51);
    CHECK(welch_psd(std::vector<double>{1.0}, 10.0).segments == 0);
    CHECK(welch_psd(x, 0.0).segments == 0);
    CHECK_THROWS_AS(estimate_frf_h1(x, y, 10.0), std::invalid_argument);
}

TEST_CASE("H1 over several records pools their segments: each record weighs by its input power", "[spectra]") {
    // Record 1: y = 2x; record 2: y = 4x with an input three times as large. Pooled,
    // H1 = (2·P + 4·9P) / (P + 9P) = 3.8 at every frequency, where averaging the two
    // records' own H1 (2 and 4) would give 3.
    std::mt19937 rng(7);
    std::normal_distribution<double> noise(0.0, 1.0);
    std::vector<double> x1(1024), x2(1024), y1(1024), y2(1024);
    for (std::size_t i = 0; i < x1.size(); ++i) {
        x1[i] = noise(rng);
        x2[i] = 3.0 * x1[i];  // the same spectrum shape, nine times the power
        y1[i] = 2.0 * x1[i];
        y2[i] = 4.0 * x2[i];
    }
    const std::span<const double> in[] = {x1, x2}, out[] = {y1, y2};
    const WelchSettings settings{128, 0.5};
    const FrfEstimate pooled = estimate_frf_h1(std::span<const std::span<const double>>(in),
                                               std::span<const std::span<const double>>(out), 1000.0, settings);
    REQUIRE(pooled.segments == 2 * estimate_frf_h1(x1, y1, 1000.0, settings).segments);
    for (std::size_t k = 1; k < pooled.h1.size(); ++k) {
        CHECK(pooled.h1[k].real() == Approx(3.8).epsilon(1e-9));
        CHECK(pooled.h1[k].imag() == Approx(0.0).margin(1e-9));
        CHECK(pooled.coherence[k] == Approx(1444.0 / 1480.0).epsilon(1e-9));  // |Σ S_xy|² / (Σ S_xx Σ S_yy): 38² / (10 · 148)
    }
    // A record shorter than the segment is left out, not allowed to change the grid.
    const std::vector<double> short_x(100, 1.0), short_y(100, 2.0);
    const std::span<const double> in3[] = {x1, short_x}, out3[] = {y1, short_y};
    const FrfEstimate with_short = estimate_frf_h1(std::span<const std::span<const double>>(in3),
                                                   std::span<const std::span<const double>>(out3), 1000.0, settings);
    CHECK(with_short.segments == estimate_frf_h1(x1, y1, 1000.0, settings).segments);
    CHECK(with_short.frequency_hz.size() == 65);
}

TEST_CASE("one Welch segment has no coherence", "[spectra]") {
    std::vector<double> x(31), y(31);
    for (std::size_t i = 0; i < x.size(); ++i) {
        x[i] = std::sin(0.3 * static_cast<double>(i)) + 0.1 * std::cos(1.7 * static_cast<double>(i * i));
        y[i] = 0.5 * x[i] + 0.2 * std::sin(2.1 * static_cast<double>(i));
    }
    const tvid::FrfEstimate one = tvid::estimate_frf_h1(x, y, 1000.0);
    REQUIRE(one.segments == 1);
    for (double c : one.coherence) CHECK(std::isnan(c));
    const tvid::FrfEstimate two = tvid::estimate_frf_h1(x, y, 1000.0, {16, 0.5});
    REQUIRE(two.segments >= 2);
    for (double c : two.coherence) CHECK(std::isfinite(c));
}

TEST_CASE("a recording is cut at its gaps: steps above 1.5 times the median", "[spectra]") {
    // 0 … 1 s and 2 … 3 s at 1 kHz, a jittered step of 1.4 ms left whole.
    std::vector<double> t;
    for (int i = 0; i <= 1000; ++i) t.push_back(i * 1e-3);
    t[500] += 0.4e-3;
    for (int i = 2000; i <= 3000; ++i) t.push_back(i * 1e-3);
    const double step = tvid::median_time_step(t);
    CHECK(step == Approx(1e-3).epsilon(1e-9));
    const auto records = tvid::gap_free_records(t, step);
    REQUIRE(records.size() == 2);
    CHECK(records[0] == std::pair<std::size_t, std::size_t>{0, 1001});
    CHECK(records[1] == std::pair<std::size_t, std::size_t>{1001, 2002});
}

}  // namespace TVID_UNITY_ID

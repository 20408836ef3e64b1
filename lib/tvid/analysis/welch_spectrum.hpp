#pragma once
// Welch's method (Welch 1967): the signal cut into segments of length L that share
// `overlap` of their samples, each segment's mean removed, a Hann window w applied, and the
// periodograms averaged. With X_k the DFT of one windowed segment, U = Σ w_i² and fs the
// sample rate, the one-sided density is
//   P_k = c_k · ⟨|X_k|²⟩ / (fs · U),   c_k = 2 for 0 < k < L/2, 1 at k = 0 and k = L/2,
// so that Σ_k P_k · fs/L is the signal's variance (Parseval). The cross spectrum
// S_xy = ⟨conj(X_k) Y_k⟩ gives the frequency response H1 = S_xy / S_xx (the estimate that is
// unbiased under output noise) and the magnitude-squared coherence |S_xy|² / (S_xx S_yy),
// 1 for a noise-free linear system and lower where noise or nonlinearity enters.

#include <complex>
#include <cstddef>
#include <span>
#include <utility>
#include <vector>

namespace tvid {

/// Welch's method: Hann-windowed segments, each with its mean removed, `overlap` shared.
struct WelchSettings {
    std::size_t segment_length = 0;  ///< 0: the largest power of two ≤ n/8, at least 64 (or n when shorter)
    double overlap = 0.5;
};

/// One-sided power spectral density in unit²/Hz at frequency_hz[k] = k·fs/segment_length.
struct Spectrum {
    std::vector<double> frequency_hz;
    std::vector<double> density;
    std::size_t segments = 0;
};

/// Fewer than 2 samples (or a sample rate that is not positive and finite): an empty
/// spectrum with segments = 0. A segment_length above n is taken as n.
Spectrum welch_psd(std::span<const double> x, double sample_rate_hz, const WelchSettings& settings = {});

/// H1 = S_xy / S_xx and the magnitude-squared coherence |S_xy|² / (S_xx S_yy), per frequency.
struct FrfEstimate {
    std::vector<double> frequency_hz;
    std::vector<std::complex<double>> h1;
    std::vector<double> coherence;
    std::size_t segments = 0;
};

/// `input` and `output` must have the same length (std::invalid_argument otherwise).
/// Where S_xx = 0, H1 is 0; where S_xx S_yy = 0, the coherence is 0. From a single
/// segment the coherence is 1 whatever the signals: it is NaN (undefined) then.
FrfEstimate estimate_frf_h1(std::span<const double> input, std::span<const double> output, double sample_rate_hz,
                            const WelchSettings& settings = {});

/// The same over several records (the windows of a split), pooled as Welch pools the
/// segments of one: S_xx, S_yy and S_xy summed over every segment of every record, no
/// segment crossing from one record into the next. Every record is cut into segments of
/// settings.segment_length (at least 2); a record shorter than that is left out.
FrfEstimate estimate_frf_h1(std::span<const std::span<const double>> inputs,
                            std::span<const std::span<const double>> outputs, double sample_rate_hz,
                            const WelchSettings& settings);

/// The segment length `settings` gives for n samples (the default rule when 0; at most n).
std::size_t welch_segment_length(std::size_t n, const WelchSettings& settings = {});

/// A time step longer than this many times the median step is a gap in the recording
/// (rows missing): no spectral segment crosses it, and it enters no sample rate.
inline constexpr double kGapStepFactor = 1.5;

/// The median of the steps time[i+1] − time[i] for i in [begin, end − 1) (0 with fewer than 2 samples).
double median_time_step(std::span<const double> time);

/// [begin, end) index ranges of `time` with no gap inside (a step above
/// kGapStepFactor × `median_step`): every spectral estimate takes its records from these.
std::vector<std::pair<std::size_t, std::size_t>> gap_free_records(std::span<const double> time, double median_step);

}  // namespace tvid

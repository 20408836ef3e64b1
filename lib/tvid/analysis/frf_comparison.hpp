#pragma once
// The model's frequency response from one input to one output, linearised at a window's
// start, beside the measured H1 estimate (Welch, analysis/welch_spectrum.hpp) of the same
// pair of channels over the estimation windows.

#include <complex>
#include <cstddef>
#include <string>
#include <vector>

#include "tvid/analysis/linear_network.hpp"
#include "tvid/analysis/torsional_modes.hpp"
#include "tvid/estimation/identification_problem.hpp"

namespace tvid {

struct FrfComparison {
    std::string input, output;            ///< the model's input and output names
    std::string input_unit, output_unit;  ///< SI, as the channels are read
    OperatingPoint operating_point;
    AngleDependence angle_dependence = AngleDependence::revolution_mean;
    double sample_rate_hz = 0.0;
    std::size_t segment_length = 0;       ///< Welch's segment (samples)
    std::size_t segments = 0;             ///< Welch's segments over every window (coherence: NaN with 1)
    double resolution_hz = 0.0;           ///< sample_rate_hz / segment_length
    std::size_t gaps = 0;                 ///< gaps in the recording the windows were cut at
    bool measured = false;                ///< whether the measured H1 is there
    std::vector<std::string> windows;     ///< the estimation windows' labels
    /// Estimation windows at another sample rate than the first, left out: "LABEL (250 Hz)".
    std::vector<std::string> left_out;
    std::vector<double> frequency_hz;     ///< k·fs/segment_length, k ≥ 1
    std::vector<std::complex<double>> model;
    std::vector<std::complex<double>> measured_h1;  ///< empty when !measured
    std::vector<double> coherence;                  ///< empty when !measured
    /// The model alone on a finer grid over the same band: the measurement's, 100 points a
    /// decade, and 17 points across each oscillating mode's half-power band, so that its
    /// peaks are resolved (for a figure).
    std::vector<double> curve_frequency_hz;
    std::vector<std::complex<double>> curve;
    /// The undamped modes' natural frequencies in the band, where |H| is infinite: the
    /// curve approaches each from both sides (to 1e-4 of f_n) and holds no point there; a
    /// grid point there has an infinite model response.
    std::vector<double> undamped_hz;
};

/// The Welch segment asked for: a length in samples, or a frequency resolution in Hz (then
/// the segment is fs/resolution samples, rounded up, so the resolution is at least as fine).
/// Neither: the default rule (welch_segment_length of the shortest window, halved until it
/// fits the longest gap-free record).
struct SpectralResolution {
    std::size_t segment = 0;
    double resolution_hz = 0.0;
};

/// The comparison for model input `input` (an index into the network's input_names) and
/// network output `output` (an index into the network's outputs, one that is measured),
/// the model linearised at estimation window `window`'s start with parameters `params`.
FrfComparison compare_frf(const IdentificationProblem& problem, const std::vector<double>& params, std::size_t input,
                          std::size_t output, std::size_t window, AngleDependence angle_dependence,
                          const SpectralResolution& asked = {});
/// A segment asked for that the windows cannot give (under 8 samples, or longer than the
/// longest gap-free record) throws std::invalid_argument, naming the finest resolution they allow.

}  // namespace tvid

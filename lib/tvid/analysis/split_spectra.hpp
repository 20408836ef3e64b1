#pragma once
// Where in frequency, or in engine order, a fit's misfit lies: the spectra of the
// measured output, the simulated output and the residual (measured − simulated) over the
// windows of a split, and the residual's dominant band or order.
//
// Windows are separate stretches of the recording: a Welch segment never crosses from one
// window into the next (nor across a non-finite sample); the segments of all windows are
// averaged together, so each window counts by its number of segments. The segment length
// is the Welch default for the split's samples (the largest power of two ≤ N/8, at least
// 64), halved until the longest stretch holds one segment; a stretch shorter than a
// segment contributes nothing. A gap in the recording (a time step above kGapStepFactor
// times the window's median step: rows missing) ends a stretch too, so no segment runs
// across it and the sample rate, the stretches' mean (samples − 1)/span, leaves it out.
// Windows of recordings at other rates (data.recordings of a 1 kHz and a 250 Hz logger)
// are not mixed: the spectra hold the stretches at the rate of most samples, and say how
// many samples at another rate they left out.

#include <cstddef>
#include <string>
#include <vector>

#include "tvid/analysis/evaluation.hpp"
#include "tvid/channels/recording_spans.hpp"
#include "tvid/analysis/order_spectrum.hpp"

namespace tvid {

struct OutputSpectra {
    std::vector<double> measured, simulated, residual;  ///< one-sided densities [unit²/Hz]
};

struct SplitSpectra {
    std::string split;                  ///< "estimation" or "validation"
    double sample_rate_hz = 0.0;
    std::size_t segment_length = 0;
    std::size_t segments = 0;           ///< 0: no stretch long enough, no spectra
    std::size_t samples = 0;            ///< in the stretches that contributed
    std::size_t gaps = 0;               ///< gaps in the recording the stretches were split at
    std::size_t other_rate_samples = 0; ///< samples of windows at another sample rate, left out
    double other_rate_hz = 0.0;         ///< that rate (the last one seen, when there are several)
    double resolution_hz = 0.0;         ///< sample_rate_hz / segment_length
    std::vector<double> frequency_hz;
    std::vector<OutputSpectra> outputs;  ///< per compared output
};

/// Every window that simulated, each output's three densities on one frequency grid.
SplitSpectra split_spectra(const SplitEvaluation& split, std::size_t outputs);

/// The residual's dominant band: the peak of the density above 0 Hz, and the share of the
/// variance (Σ P Δf, the density's integral) in the band f_peak ± max(2 Δf, 5 % of f_peak).
struct SpectralPeak {
    bool available = false;
    double peak_hz = 0.0;
    double band_low_hz = 0.0, band_high_hz = 0.0;
    double share = 0.0;     ///< of the variance, in the band
    double variance = 0.0;  ///< the density's integral [unit²]
};
SpectralPeak dominant_band(const std::vector<double>& frequency_hz, const std::vector<double>& density);

/// One output's order spectra in one engine cycle of one window.
struct CycleOrders {
    std::size_t output = 0;
    std::string window;
    CycleOrderSpectrum measured, simulated, residual;
};

struct SplitOrders {
    std::string split;
    std::vector<CycleOrders> cycles;  ///< by window, then cycle, then output
};

/// The order spectra of each complete engine cycle in the windows that simulated.
/// `crank_angle_rad` is the recording's cumulative crank angle per sample; cycles are
/// counted as the experiment's `cycle:` windows count them, from the first cycle start at or
/// after the recording's first angle. With several recordings end to end (`recordings`, the
/// rows of each), each window's cycles are counted in its own recording.
SplitOrders split_orders(const SplitEvaluation& split, std::size_t outputs, const std::vector<double>& crank_angle_rad,
                         const OrderSettings& settings = {}, const std::vector<RowSpan>& recordings = {});

/// The residual's dominant order for one output: the order of the largest mean A²/2 over
/// the cycles, and its share of their mean variance; and the share of all the orders listed.
struct OrderPeak {
    bool available = false;
    double order = 0.0;
    double amplitude = 0.0;  ///< RMS over the cycles of A_o [unit]
    double share = 0.0;
    double orders_share = 0.0;  ///< of the variance, in the orders up to the highest listed (the rest: higher orders, noise)
    double max_order = 0.0;     ///< that highest order
    double variance = 0.0;   ///< mean over the cycles of the residual's variance [unit²]
    std::size_t cycles = 0;
};
OrderPeak dominant_order(const SplitOrders& orders, std::size_t output);

}  // namespace tvid

#pragma once
// The spectra of a fit's report (docs/report-format.md): spectra.csv (the Welch densities
// of the measured output, the simulated output and the residual per split), orders.csv
// (per engine cycle, the orders' amplitudes and phases; engine experiments only) and the
// residual's dominant band or order per output (summary.json `residual_spectrum`, the
// terminal's summary).

#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "tvid/analysis/evaluation.hpp"
#include "tvid/analysis/residual_whiteness.hpp"
#include "tvid/analysis/split_spectra.hpp"
#include "tvid/experiment/experiment.hpp"

namespace tvid {

/// The highest order orders.csv lists.
constexpr double kReportMaxOrder = 12.0;

/// An output's density unit from its unit: "N m" → "(N m)^2/Hz", "rad" → "rad^2/Hz".
std::string density_unit(const std::string& unit);

/// The experiment has a crank angle (data.angle): its report holds orders.csv.
bool has_order_spectra(const Experiment& ex);

/// spectra.csv: `split,frequency [Hz]`, then per output `OUT_measured_psd [U]`,
/// `OUT_simulated_psd [U]`, `OUT_residual_psd [U]` (U its density unit); the estimation
/// split's rows, then the validation split's.
std::string spectra_csv(const Experiment& ex, const Evaluation& ev);

/// orders.csv: `split,window,cycle,output,unit,order,` and the amplitude (in `unit`) and
/// phase [deg] of the measured output, the simulated output and the residual; empty for an
/// experiment without crank angle.
std::string orders_csv(const Experiment& ex, const Evaluation& ev);

/// One output's residual spectrum over a split's windows.
struct ResidualSpectrumSummary {
    std::string output, unit;
    SpectralPeak band;   ///< the dominant frequency band
    /// The spectrum it was read from: Welch segments, their length, its resolution and
    /// the recording's gaps no segment crosses (split_spectra.hpp).
    std::size_t segments = 0, segment_length = 0, gaps = 0;
    double resolution_hz = 0.0;
    /// Samples of windows at another sample rate than the spectrum's (recordings of
    /// several rates), left out of it, and that rate.
    std::size_t other_rate_samples = 0;
    double other_rate_hz = 0.0;
    OrderPeak order;     ///< the dominant order (experiments with a crank angle)
    bool engine = false; ///< an input is read by crank angle (cylinder pressures): the order is the view
};
std::vector<ResidualSpectrumSummary> residual_spectrum_summary(const Experiment& ex, const SplitEvaluation& split);

/// summary.json's `residual_spectrum` block: per split, per output.
nlohmann::json residual_spectrum_json(const Experiment& ex, const Evaluation& ev);

/// The terminal's line for one output: "residual OUT: 38 % of its variance at 52–56 Hz
/// (peak 54.1 Hz)", or at an order for an engine (an input read by crank angle); empty
/// when nothing was assessed. A residual that passes the whiteness test (`whiteness`,
/// fit/fit_verdict.hpp's residual_is_white) has no band worth naming: "residual OUT: white
/// (Ljung-Box p 0.65 over 20 lags), no band stands out".
std::string residual_spectrum_line(const ResidualSpectrumSummary& s, const ResidualWhiteness* whiteness = nullptr);

}  // namespace tvid

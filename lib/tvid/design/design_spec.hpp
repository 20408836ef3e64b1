#pragma once
// The design: section of an experiment (docs/experiment-design.md): which model input
// `tvid design` excites, over how long and at which sample rate, in which band and range,
// about which operating point, and the outputs' noise the prediction assumes.

#include <cstddef>
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "tvid/experiment/experiment.hpp"

namespace tvid {

/// What a design is judged by; each is a relative standard error (lower is better) of the
/// free parameters, each scaled by its nominal value: the geometric mean over the
/// covariance's principal axes (D-optimal), the root mean square (A-optimal), the largest.
enum class DesignCriterion { d_optimal, a_optimal, worst_relative_se };
const char* to_string(DesignCriterion c);

struct DesignSpec {
    std::size_t input = 0;        ///< the designed input: an index into Experiment::inputs (a time input)
    double duration = 0.0;        ///< [s] of the designed record
    double sample_rate = 0.0;     ///< [Hz]
    double band_low = 0.0, band_high = 0.0;  ///< [Hz] the excitation's band
    double limit_low = 0.0, limit_high = 0.0;  ///< the input's range, in its channel's unit
    double rms = 0.0;             ///< of the input about `base`, in its channel's unit
    double base = 0.0;            ///< the input's level at the operating point, in its channel's unit
    /// Every time input's level while the design plays, in its channel's unit, per
    /// Experiment::inputs (the designed input's entry is `base`; 0 for the others unless held).
    std::vector<double> levels;
    std::vector<double> noise;    ///< each output's noise standard deviation, SI, per Experiment::outputs
    std::vector<double> noise_given;  ///< the same in the channel's unit, as written
    DesignCriterion criterion = DesignCriterion::d_optimal;
    int bands = 8;                ///< the designed multisine's bands, log-spaced across the band
    int evaluations = 60;         ///< the design search's trial inputs at most
    /// robust: the criterion averaged over the nominal values and `draws` parameter sets drawn
    /// about them (design/parameter_draws.hpp); 0: the nominal values alone.
    int draws = 0;
    double draw_spread = 0.3;     ///< each free parameter's factor within [1/(1 + spread), 1 + spread]
    std::uint64_t draw_seed = 1;
    SourceLocation where;         ///< the design: section
    SourceLocation rms_where;     ///< design.rms, for a range that cannot hold it

    std::size_t samples() const;  ///< round(duration * sample_rate) + 1
};

/// Reads and checks `design:` of the experiment `ex` was loaded from (with the same
/// overrides). Throws InputError naming file, line and key: no design section, an input
/// that is not a time input of the model, a band beyond the Nyquist frequency or holding no
/// frequency of the record's grid (multiples of 1/duration), limits that exclude the
/// operating point, a noise level that is not positive or an output without one, an
/// estimated start (the prediction takes the start as known).
DesignSpec read_design_spec(const Experiment& ex, const std::vector<Override>& overrides);

}  // namespace tvid

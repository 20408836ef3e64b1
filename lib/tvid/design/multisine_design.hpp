#pragma once
// The designed input: a multisine on the record's frequency grid within the band whose
// power is shared among a few bands (log-spaced across the band), the shares chosen to
// minimise the design's criterion of the predicted standard errors. Each trial share is a
// multisine with Schroeder's phases for its amplitudes (a low crest factor for any
// spectrum), scaled to the design's RMS within its limits and simulated with its exact
// sensitivities (design/predicted_uncertainty.hpp); NLopt's BOBYQA (derivative-free,
// deterministic) searches the bands' log powers from the flat multisine.

#include <vector>

#include "tvid/design/design_spec.hpp"
#include "tvid/design/predicted_uncertainty.hpp"
#include "tvid/experiment/experiment.hpp"

namespace tvid {

/// Σ_k A_k cos(2π f_k t + φ_k) over the record's grid frequencies f_k = k / T within
/// [f_low, f_high] (T = samples / sample_rate), A_k² the power of the band of f_k (`edges`:
/// B + 1 increasing band edges, the band's power `band_power[b]` shared equally by its
/// lines), with Schroeder's phases for that spectrum: φ_k = −2π Σ_{l<k} (k − l) p_l, p_l the
/// share of line l in the total power.
std::vector<double> banded_multisine_shape(const std::vector<double>& time, double sample_rate,
                                           const std::vector<double>& edges, const std::vector<double>& band_power);

/// B + 1 band edges spaced evenly on a log scale from the band's first grid line to its high end.
std::vector<double> design_band_edges(const DesignSpec& spec, int bands);

struct MultisineDesign {
    std::vector<double> edges;       ///< the bands' edges [Hz]
    std::vector<double> band_power;  ///< each band's share of the power, summing to 1
    std::vector<double> value;       ///< the designed input, in its channel's unit
    double flat_criterion = 0.0;     ///< the (averaged) criterion of the flat multisine, where the search starts
    double criterion = 0.0;          ///< the designed input's (averaged) criterion
    int evaluations = 0;             ///< trial inputs the search scored
};

/// The search, `spec.evaluations` trial inputs at most, each scored by the criterion
/// averaged over the parameter sets (full vectors; design_parameter_sets: the nominal one
/// first): one simulation with sensitivities per set and trial.
MultisineDesign design_multisine(const Experiment& ex, const DesignSpec& spec,
                                 const std::vector<std::vector<double>>& parameter_sets);

}  // namespace tvid

#include "tvid/analysis/frf_comparison.hpp"

#include <algorithm>
#include <cmath>
#include <span>
#include <stdexcept>

#include "tvid/analysis/welch_spectrum.hpp"
#include "tvid/model/parameter_units.hpp"

namespace tvid {

FrfComparison compare_frf(const IdentificationProblem& problem, const std::vector<double>& params, std::size_t input,
                          std::size_t output, std::size_t window, AngleDependence angle_dependence) {
    const ProblemDefinition& d = problem.definition();
    FrfComparison r;
    r.input = d.network.input_names.at(input);
    r.output = d.network.outputs.at(output).name;
    r.input_unit = input_unit(d.network, input);
    r.output_unit = output_unit(d.network.outputs[output]);
    r.angle_dependence = angle_dependence;
    r.operating_point = window_operating_point(problem, params, window);
    const LinearNetwork sys = linearise_network(d.network, params, &d.angle_inputs, r.operating_point.x,
                                                r.operating_point.u, angle_dependence);

    std::size_t measured_index = d.output_indices.size();
    for (std::size_t k = 0; k < d.output_indices.size(); ++k)
        if (static_cast<std::size_t>(d.output_indices[k]) == output) measured_index = k;
    if (measured_index == d.output_indices.size())
        throw std::runtime_error("output " + r.output + " is not measured: there is no H1 to compare with");

    // Every estimation window on one frequency grid: the segment of the shortest.
    std::size_t shortest = 0;
    for (const Window& w : d.estimation) {
        const std::size_t n = w.last + 1 - w.first;
        shortest = shortest == 0 ? n : std::min(shortest, n);
        r.windows.push_back(w.label);
    }
    const std::vector<double>& time = d.inputs.time();
    const Window& w0 = d.estimation.front();
    r.sample_rate_hz = static_cast<double>(w0.last - w0.first) / (time[w0.last] - time[w0.first]);
    r.segment_length = welch_segment_length(shortest);
    if (r.segment_length < 8) throw std::runtime_error("the estimation windows are too short for a spectrum (under 8 samples)");

    // H1 over the windows, their segments pooled (no segment crosses a window gap).
    const WelchSettings settings{r.segment_length, 0.5};
    auto ws = problem.make_workspace();  // the channels as `params` delay them
    problem.use_parameters(params, *ws);
    std::vector<std::vector<double>> in, out;
    for (const Window& w : d.estimation) {
        in.emplace_back();
        out.emplace_back();
        for (std::size_t i = w.first; i <= w.last; ++i) {
            in.back().push_back(ws->inputs->value(input, i));
            out.back().push_back((*ws->measured[measured_index])[i]);
        }
    }
    const std::vector<std::span<const double>> in_records(in.begin(), in.end()), out_records(out.begin(), out.end());
    const FrfEstimate e = estimate_frf_h1(in_records, out_records, r.sample_rate_hz, settings);
    r.segments = e.segments;
    r.measured = r.segments > 0;
    for (std::size_t k = 1; k <= settings.segment_length / 2; ++k) {
        r.frequency_hz.push_back(static_cast<double>(k) * r.sample_rate_hz / static_cast<double>(r.segment_length));
        if (r.measured) {
            r.measured_h1.push_back(e.h1[k]);
            r.coherence.push_back(e.coherence[k]);
        }
    }
    r.model = frequency_response(sys, input, output, r.frequency_hz);

    const double lo = r.frequency_hz.front(), hi = r.frequency_hz.back();
    const auto points = static_cast<std::size_t>(std::ceil(100.0 * std::log10(hi / lo)));
    for (std::size_t k = 0; k <= points; ++k)
        r.curve_frequency_hz.push_back(lo * std::pow(hi / lo, static_cast<double>(k) / static_cast<double>(std::max<std::size_t>(points, 1))));
    const ModalAnalysis modal = torsional_modes(sys, node_ratios(d.network, params, 0), 0);
    // Each oscillating mode's half-power band, ±ζ·f_n around its damped frequency, in 8 steps.
    for (const TorsionalMode& m : modal.modes) {
        if (m.kind != ModeKind::oscillating) continue;
        for (int step = -8; step <= 8; ++step) {
            const double f = m.damped_frequency_hz + step * m.damping_ratio * m.frequency_hz / 8.0;
            if (f > lo && f < hi) r.curve_frequency_hz.push_back(f);
        }
    }
    r.curve_frequency_hz.insert(r.curve_frequency_hz.end(), r.frequency_hz.begin(), r.frequency_hz.end());
    std::sort(r.curve_frequency_hz.begin(), r.curve_frequency_hz.end());
    r.curve_frequency_hz.erase(std::unique(r.curve_frequency_hz.begin(), r.curve_frequency_hz.end()),
                               r.curve_frequency_hz.end());
    r.curve = frequency_response(sys, input, output, r.curve_frequency_hz);
    return r;
}

}  // namespace tvid

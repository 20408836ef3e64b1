#include "tvid/analysis/frf_comparison.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <span>
#include <stdexcept>

#include "tvid/analysis/welch_spectrum.hpp"
#include "tvid/model/parameter_units.hpp"

namespace tvid {

namespace {

/// The estimation windows' gap-free sample ranges [first, last + 1) on one frequency grid.
struct FrfRecords {
    std::vector<std::pair<std::size_t, std::size_t>> ranges;
    std::size_t shortest = 0;  ///< the shortest window taken (samples)
    std::size_t longest = 0;   ///< the longest gap-free range (samples)
};

/// Every estimation window on one frequency grid, each cut at its recording's gaps (a
/// step above kGapStepFactor times the window's own median step): no segment crosses a
/// window's end or a gap, and the sample rate leaves the gaps out. A window at another
/// sample rate than the first (a recording of another logger) would put its lines at
/// the wrong frequencies: it is left out, and named. Sets r's sample rate, windows,
/// left_out and gaps.
FrfRecords estimation_records(const ProblemDefinition& d, FrfComparison& r) {
    const std::vector<double>& time = d.inputs.time();
    FrfRecords records;
    constexpr double kSameRate = 1e-3;  // relative: a logger's clock jitters
    for (const Window& w : d.estimation) {
        const std::size_t n = w.last + 1 - w.first;
        const std::span<const double> span(time.data() + w.first, n);
        const auto pieces = gap_free_records(span, median_time_step(span));
        double steps = 0.0, seconds = 0.0;
        for (const auto& [from, to] : pieces) {
            steps += static_cast<double>(to - from - 1);
            seconds += time[w.first + to - 1] - time[w.first + from];
        }
        const double rate = seconds > 0 ? steps / seconds : 0.0;
        if (records.ranges.empty() && r.windows.empty()) r.sample_rate_hz = rate;
        if (!(std::abs(rate - r.sample_rate_hz) <= kSameRate * r.sample_rate_hz)) {
            char text[64];
            std::snprintf(text, sizeof text, " (%.4g Hz)", rate);
            r.left_out.push_back(w.label + text);
            continue;
        }
        records.shortest = records.shortest == 0 ? n : std::min(records.shortest, n);
        r.windows.push_back(w.label);
        r.gaps += pieces.size() - 1;
        for (const auto& [from, to] : pieces) {
            records.ranges.emplace_back(w.first + from, w.first + to);
            records.longest = std::max(records.longest, to - from);
        }
    }
    return records;
}

/// Welch's segment: the one asked for, or the default rule. Sets r's segment_length and resolution_hz.
void choose_segment(const SpectralResolution& asked, const FrfRecords& records, FrfComparison& r) {
    if (asked.segment > 0 || asked.resolution_hz > 0) {
        r.segment_length = asked.segment > 0 ? asked.segment
                                             : static_cast<std::size_t>(std::ceil(r.sample_rate_hz / asked.resolution_hz));
        if (r.segment_length < 8 || r.segment_length > records.longest) {
            char finest[64];
            std::snprintf(finest, sizeof finest, "%.4g", r.sample_rate_hz / static_cast<double>(records.longest));
            throw std::invalid_argument("a segment of " + std::to_string(r.segment_length) +
                                        " samples does not fit: the longest gap-free estimation record has " +
                                        std::to_string(records.longest) + " samples (finest resolution " + finest +
                                        " Hz), and a segment needs at least 8");
        }
    } else {
        r.segment_length = welch_segment_length(records.shortest);
        while (r.segment_length > records.longest && r.segment_length / 2 >= 8) r.segment_length /= 2;
    }
    if (r.segment_length < 8 || !(r.sample_rate_hz > 0) || !std::isfinite(r.sample_rate_hz))
        throw std::runtime_error("the estimation windows are too short for a spectrum (under 8 samples)");
    r.resolution_hz = r.sample_rate_hz / static_cast<double>(r.segment_length);
}

/// H1 over the records, their segments pooled, on the grid k·fs/segment_length (k ≥ 1).
void measure_h1(const IdentificationProblem& problem, const std::vector<double>& params, std::size_t input,
                std::size_t measured_index, const FrfRecords& records, FrfComparison& r) {
    const WelchSettings settings{r.segment_length, 0.5};
    auto ws = problem.make_workspace();  // the channels as `params` delay them
    problem.use_parameters(params, *ws);
    std::vector<std::vector<double>> in, out;
    for (const auto& [from, to] : records.ranges) {
        in.emplace_back();
        out.emplace_back();
        for (std::size_t i = from; i < to; ++i) {
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
}

/// The model's curve on a finer grid than the measurement's (100 points a decade, and
/// each oscillating mode's half-power band resolved); the undamped modes' frequencies are
/// approached from both sides and left out.
void model_curve(const LinearNetwork& sys, const ModalAnalysis& modal, std::size_t input, std::size_t output,
                 FrfComparison& r) {
    const double lo = r.frequency_hz.front(), hi = r.frequency_hz.back();
    const auto points = static_cast<std::size_t>(std::ceil(100.0 * std::log10(hi / lo)));
    for (std::size_t k = 0; k <= points; ++k)
        r.curve_frequency_hz.push_back(lo * std::pow(hi / lo, static_cast<double>(k) / static_cast<double>(std::max<std::size_t>(points, 1))));
    // Each oscillating mode's half-power band, ±ζ·f_n around its damped frequency, in 8 steps.
    for (const TorsionalMode& m : modal.modes) {
        if (m.kind != ModeKind::oscillating) continue;
        if (!(m.damping_ratio > 0.0)) {
            // Undamped: |H| is infinite at f_n, where the solve would return rounding. The
            // curve approaches it from both sides instead, and the resonance is stated.
            r.undamped_hz.push_back(m.frequency_hz);
            for (const double offset : {1e-2, 3e-3, 1e-3, 3e-4, 1e-4})
                for (const double f : {m.frequency_hz * (1 - offset), m.frequency_hz * (1 + offset)})
                    if (f > lo && f < hi) r.curve_frequency_hz.push_back(f);
            continue;
        }
        for (int step = -8; step <= 8; ++step) {
            const double f = m.damped_frequency_hz + step * m.damping_ratio * m.frequency_hz / 8.0;
            if (f > lo && f < hi) r.curve_frequency_hz.push_back(f);
        }
    }
    r.curve_frequency_hz.insert(r.curve_frequency_hz.end(), r.frequency_hz.begin(), r.frequency_hz.end());
    std::sort(r.curve_frequency_hz.begin(), r.curve_frequency_hz.end());
    r.curve_frequency_hz.erase(std::unique(r.curve_frequency_hz.begin(), r.curve_frequency_hz.end()),
                               r.curve_frequency_hz.end());
    // No point at an undamped resonance itself (within 1e-6 of it: the solve there is rounding).
    const auto at_undamped = [&](double f) {
        for (const double fn : r.undamped_hz)
            if (std::abs(f - fn) <= 1e-6 * fn) return true;
        return false;
    };
    std::erase_if(r.curve_frequency_hz, at_undamped);
    r.curve = frequency_response(sys, input, output, r.curve_frequency_hz);
    for (std::size_t k = 0; k < r.frequency_hz.size(); ++k)
        if (at_undamped(r.frequency_hz[k])) r.model[k] = std::numeric_limits<double>::infinity();
}

}  // namespace

FrfComparison compare_frf(const IdentificationProblem& problem, const std::vector<double>& params, std::size_t input,
                          std::size_t output, std::size_t window, AngleDependence angle_dependence,
                          const SpectralResolution& asked) {
    const ProblemDefinition& d = problem.definition();
    FrfComparison r;
    r.input = d.network.input_names.at(input);
    r.output = d.network.outputs.at(output).name;
    r.input_unit = input_unit(d.network, input);
    r.output_unit = output_unit(d.network, d.network.outputs[output]);
    r.angle_dependence = angle_dependence;
    r.operating_point = window_operating_point(problem, params, window);
    const LinearNetwork sys = linearise_network(d.network, params, &d.angle_inputs, r.operating_point.x,
                                                r.operating_point.u, angle_dependence);

    std::size_t measured_index = d.output_indices.size();
    for (std::size_t k = 0; k < d.output_indices.size(); ++k)
        if (static_cast<std::size_t>(d.output_indices[k]) == output) measured_index = k;
    if (measured_index == d.output_indices.size())
        throw std::runtime_error("output " + r.output + " is not measured: there is no H1 to compare with");

    const FrfRecords records = estimation_records(d, r);
    choose_segment(asked, records, r);
    measure_h1(problem, params, input, measured_index, records, r);
    r.model = frequency_response(sys, input, output, r.frequency_hz);
    model_curve(sys, torsional_modes(sys, node_ratios(d.network, params, 0), 0), input, output, r);
    return r;
}

}  // namespace tvid

#include "tvid/design/multisine_design.hpp"

#include <nlopt.hpp>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

#include "tvid/design/design_experiment.hpp"
#include "tvid/design/excitation_signals.hpp"
#include "tvid/design/parameter_draws.hpp"
#include "tvid/util/stop_request.hpp"

namespace tvid {

std::vector<double> banded_multisine_shape(const std::vector<double>& time, double sample_rate,
                                           const std::vector<double>& edges, const std::vector<double>& band_power) {
    std::vector<double> s(time.size(), 0.0);
    const double T = static_cast<double>(time.size()) / sample_rate;
    const auto first = static_cast<long>(std::max(1.0, std::ceil(edges.front() * T - 1e-9)));
    const auto last = static_cast<long>(std::floor(edges.back() * T + 1e-9));
    if (last < first) return s;
    // Each line's band, and each band's count of lines.
    const std::size_t bands = band_power.size();
    std::vector<std::size_t> band_of;
    std::vector<double> lines(bands, 0.0);
    for (long k = first; k <= last; ++k) {
        const double f = static_cast<double>(k) / T;
        std::size_t b = 0;
        while (b + 1 < bands && f >= edges[b + 1]) ++b;
        band_of.push_back(b);
        lines[b] += 1.0;
    }
    std::vector<double> power(band_of.size());
    double total = 0.0;
    for (std::size_t i = 0; i < band_of.size(); ++i) {
        power[i] = band_power[band_of[i]] / lines[band_of[i]];
        total += power[i];
    }
    if (!(total > 0)) return s;
    // Schroeder's phases for this spectrum (Schroeder 1970, eq. 11): φ_k = −2π Σ_{l<k} (k − l) p_l.
    double cumulative = 0.0, weighted = 0.0, phase = 0.0;
    for (std::size_t i = 0; i < power.size(); ++i) {
        // Σ_{l<i} (i − l) p_l grows by Σ_{l<i} p_l from i − 1 to i.
        if (i > 0) weighted += cumulative;
        phase = -2 * std::numbers::pi * weighted;
        cumulative += power[i] / total;
        const double amplitude = std::sqrt(power[i]);
        if (amplitude == 0.0) continue;
        const double w = 2 * std::numbers::pi * static_cast<double>(first + static_cast<long>(i)) / T;
        for (std::size_t j = 0; j < time.size(); ++j) s[j] += amplitude * std::cos(w * (time[j] - time.front()) + phase);
    }
    return s;
}

std::vector<double> design_band_edges(const DesignSpec& spec, int bands) {
    const double df = spec.sample_rate / static_cast<double>(spec.samples());
    const double low = std::max(spec.band_low, df), high = spec.band_high;
    std::vector<double> edges(static_cast<std::size_t>(bands) + 1);
    for (int b = 0; b <= bands; ++b)
        edges[static_cast<std::size_t>(b)] = low * std::pow(high / low, static_cast<double>(b) / bands);
    edges.front() = std::max(spec.band_low, 0.0);
    edges.back() = high;
    return edges;
}

namespace {

struct Search {
    const Experiment* ex;
    const DesignSpec* spec;
    const std::vector<std::vector<double>>* sets;
    std::vector<double> time, edges;
    int evaluations = 0;
    double best = std::numeric_limits<double>::infinity();
    std::vector<double> best_power{}, best_value{};
};

std::vector<double> shares(const std::vector<double>& log_power) {
    std::vector<double> p(log_power.size());
    double sum = 0.0;
    for (std::size_t b = 0; b < p.size(); ++b) sum += p[b] = std::pow(10.0, log_power[b]);
    for (double& v : p) v /= sum;
    return p;
}

// The criterion of the input with these bands' log powers; a candidate that cannot meet
// the RMS within the limits, or does not simulate, or leaves a parameter undetermined,
// scores far above any real one.
double trial(const std::vector<double>& log_power, std::vector<double>&, void* data) {
    Search& s = *static_cast<Search*>(data);
    if (stop_requested()) throw nlopt::forced_stop();
    ++s.evaluations;
    const std::vector<double> power = shares(log_power);
    const std::vector<double> shape = banded_multisine_shape(s.time, s.spec->sample_rate, s.edges, power);
    const auto value = scaled_excitation(shape, s.spec->base, s.spec->rms, s.spec->limit_low, s.spec->limit_high);
    if (!value) return 1e30;
    const Experiment record = design_experiment(*s.ex, *s.spec, s.time, *value);
    std::vector<PredictedUncertainty> predictions;
    for (const std::vector<double>& params : *s.sets) {
        predictions.push_back(predict_uncertainty(record, params, s.spec->noise));
        if (!predictions.back().simulated) return 1e30;
    }
    const double c = averaged_criterion(predictions, s.spec->criterion);
    if (!std::isfinite(c)) return 1e30;
    if (c < s.best) {
        s.best = c;
        s.best_power = power;
        s.best_value = *value;
    }
    return std::log(c);
}

}  // namespace

MultisineDesign design_multisine(const Experiment& ex, const DesignSpec& spec,
                                 const std::vector<std::vector<double>>& parameter_sets) {
    Search s{&ex, &spec, &parameter_sets, excitation_time_grid(spec.samples(), spec.sample_rate), design_band_edges(spec, spec.bands)};
    const auto n = static_cast<unsigned>(spec.bands);
    std::vector<double> x(n, 0.0);  // the flat multisine: every band at the same power per band
    // Each band's power per line equal at the start: log10 of its share of the lines.
    {
        const double T = static_cast<double>(s.time.size()) / spec.sample_rate;
        for (unsigned b = 0; b < n; ++b) {
            const double lo = std::max(s.edges[b] * T - 1e-9, b == 0 ? 1.0 - 1e-9 : -1.0);
            const double hi = s.edges[b + 1] * T + (b + 1 == n ? 1e-9 : -1e-9);
            const double lines = std::max(0.0, std::floor(hi) - std::ceil(lo) + 1);
            x[b] = lines > 0 ? std::log10(lines) : -6.0;
        }
    }
    MultisineDesign d;
    d.edges = s.edges;
    std::vector<double> unused;
    const double flat = trial(x, unused, &s);
    d.flat_criterion = std::isfinite(s.best) ? s.best : std::numeric_limits<double>::infinity();
    nlopt::opt opt(nlopt::LN_BOBYQA, n);
    const double top = *std::max_element(x.begin(), x.end());
    opt.set_lower_bounds(std::vector<double>(n, top - 4.0));  // a band at least 1e-4 of the strongest's power
    opt.set_upper_bounds(std::vector<double>(n, top + 1.0));
    for (double& v : x) v = std::clamp(v, top - 4.0, top + 1.0);
    opt.set_min_objective(trial, &s);
    opt.set_maxeval(std::max(1, spec.evaluations - 1));
    opt.set_initial_step(0.5);
    opt.set_xtol_abs(1e-3);
    double value = flat;
    try {
        opt.optimize(x, value);
    } catch (const nlopt::forced_stop&) {
    } catch (const nlopt::roundoff_limited&) {
    }
    d.band_power = s.best_power;
    d.value = s.best_value;
    d.criterion = s.best;
    d.evaluations = s.evaluations;
    return d;
}

}  // namespace tvid

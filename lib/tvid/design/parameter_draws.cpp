#include "tvid/design/parameter_draws.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>

#include "tvid/util/splitmix64.hpp"

namespace tvid {

namespace {
// Uniform in [-1, 1).
double symmetric(std::uint64_t& state) { return static_cast<double>(splitmix64(state) >> 11) * 0x1.0p-52 - 1.0; }
}  // namespace

std::vector<std::vector<double>> design_parameter_sets(const Experiment& ex, const DesignSpec& spec,
                                                       const std::vector<double>& nominal) {
    std::vector<std::vector<double>> sets{nominal};
    std::uint64_t state = spec.draw_seed;
    const double log_factor = std::log1p(spec.draw_spread);
    for (int d = 0; d < spec.draws; ++d) {
        std::vector<double> p = nominal;
        for (std::size_t i = 0; i < ex.parameters.size(); ++i) {
            const ParameterSetting& s = ex.parameters[i];
            const double u = symmetric(state);  // drawn for every parameter: the stream does not depend on which are free
            if (s.fixed || !s.expr.empty()) continue;
            p[i] = std::clamp(nominal[i] * std::exp(u * log_factor), s.min, s.max);
        }
        sets.push_back(std::move(p));
    }
    return sets;
}

double averaged_criterion(const std::vector<PredictedUncertainty>& predictions, DesignCriterion c) {
    double sum = 0.0;
    for (const PredictedUncertainty& u : predictions) {
        const double v = u.simulated ? u.criterion(c) : std::numeric_limits<double>::infinity();
        if (!std::isfinite(v) || !(v > 0)) return std::numeric_limits<double>::infinity();
        sum += std::log(v);
    }
    return predictions.empty() ? std::numeric_limits<double>::infinity()
                               : std::exp(sum / static_cast<double>(predictions.size()));
}

}  // namespace tvid

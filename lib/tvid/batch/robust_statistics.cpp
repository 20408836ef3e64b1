#include "tvid/batch/robust_statistics.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace tvid {

namespace {

constexpr double kNoStatistic = std::numeric_limits<double>::quiet_NaN();

std::vector<double> finite_values(const std::vector<double>& values) {
    std::vector<double> out;
    for (double v : values)
        if (std::isfinite(v)) out.push_back(v);
    return out;
}

}  // namespace

double median(std::vector<double> values) {
    values = finite_values(values);
    if (values.empty()) return kNoStatistic;
    std::sort(values.begin(), values.end());
    const std::size_t n = values.size();
    return n % 2 == 1 ? values[n / 2] : 0.5 * (values[n / 2 - 1] + values[n / 2]);
}

double median_absolute_deviation(const std::vector<double>& values) {
    const double m = median(values);
    if (!std::isfinite(m)) return kNoStatistic;
    std::vector<double> deviations;
    for (double v : finite_values(values)) deviations.push_back(std::abs(v - m));
    return median(deviations);
}

std::vector<double> robust_z_scores(const std::vector<double>& values) {
    std::vector<double> z(values.size(), kNoStatistic);
    const double m = median(values);
    const double mad = median_absolute_deviation(values);
    if (!std::isfinite(mad) || mad <= 0.0) return z;
    for (std::size_t i = 0; i < values.size(); ++i)
        if (std::isfinite(values[i])) z[i] = kRobustZFactor * (values[i] - m) / mad;
    return z;
}

Stability stability(const std::vector<double>& values) {
    const std::vector<double> x = finite_values(values);
    constexpr double none = kNoStatistic;
    Stability s{x.size(), none, none, none, none, none, none, none};
    if (x.empty()) return s;
    double sum = 0.0;
    for (double v : x) sum += v;
    s.mean = sum / static_cast<double>(x.size());
    if (x.size() > 1) {
        double sq = 0.0;
        for (double v : x) sq += (v - s.mean) * (v - s.mean);
        s.std_dev = std::sqrt(sq / static_cast<double>(x.size() - 1));
        if (s.mean != 0.0) s.cv = s.std_dev / std::abs(s.mean);
    }
    s.median = median(x);
    s.mad = median_absolute_deviation(x);
    s.min = *std::min_element(x.begin(), x.end());
    s.max = *std::max_element(x.begin(), x.end());
    return s;
}

}  // namespace tvid

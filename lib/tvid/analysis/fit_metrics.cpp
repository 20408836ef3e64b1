#include "tvid/analysis/fit_metrics.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace tvid {

double residual_ratio_floor(const std::vector<double>& measured) {
    double largest = 0.0;
    for (double y : measured)
        if (std::isfinite(y)) largest = std::max(largest, std::abs(y));
    return kResidualRatioFloor * largest;
}

double residual_ratio(double measured, double simulated, double floor) {
    if (measured == 0.0 || !(std::abs(measured) >= floor)) return std::numeric_limits<double>::quiet_NaN();
    return (measured - simulated) / measured;
}

FitMetrics compute_fit_metrics(const std::vector<double>& measured, const std::vector<double>& simulated,
                               double offset) {
    FitMetrics m;
    const std::size_t n = std::min(measured.size(), simulated.size());
    m.samples = n;
    if (n == 0) {  // nothing scored (e.g. no validation windows): no metric is defined
        const double nan = std::numeric_limits<double>::quiet_NaN();
        m.mean_abs_error = m.sum_sq_error = m.rmse = m.e0 = m.q_index = m.fit_percent = m.max_abs_residual_ratio =
            m.residual_ratio_min_abs_y = nan;
        return m;
    }
    double abs_sum = 0.0, e0_sum = 0.0, mean = 0.0;
    for (std::size_t i = 0; i < n; ++i) mean += measured[i];
    mean /= static_cast<double>(n);
    double spread_sq = 0.0;
    const double floor = residual_ratio_floor(measured);
    m.residual_ratio_min_abs_y = std::numeric_limits<double>::quiet_NaN();
    for (std::size_t i = 0; i < n; ++i) {
        const double e = simulated[i] - measured[i];
        abs_sum += std::abs(e);
        m.sum_sq_error += e * e;
        e0_sum += std::abs(measured[i] - offset);
        spread_sq += (measured[i] - mean) * (measured[i] - mean);
        const double r = residual_ratio(measured[i], simulated[i], floor);
        if (!std::isfinite(r)) continue;
        m.max_abs_residual_ratio = std::max(m.max_abs_residual_ratio, std::abs(r));
        if (!(std::abs(measured[i]) >= m.residual_ratio_min_abs_y)) m.residual_ratio_min_abs_y = std::abs(measured[i]);
    }
    const double dn = static_cast<double>(n);
    m.mean_abs_error = abs_sum / dn;
    m.rmse = std::sqrt(m.sum_sq_error / dn);
    m.e0 = e0_sum / dn;
    m.q_index = m.e0 > 0 ? (1.0 - m.mean_abs_error / m.e0) * 100.0 : std::numeric_limits<double>::quiet_NaN();
    m.fit_percent = spread_sq > 0 ? 100.0 * (1.0 - std::sqrt(m.sum_sq_error) / std::sqrt(spread_sq))
                                  : std::numeric_limits<double>::quiet_NaN();
    return m;
}

}  // namespace tvid

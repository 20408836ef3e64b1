#include "tvid/analysis/robust_covariance.hpp"

#include <algorithm>
#include <cmath>

namespace tvid {

Eigen::MatrixXd long_run_score_covariance(const Eigen::MatrixXd& js, const std::vector<double>& r, std::size_t outputs,
                                          const std::vector<std::size_t>& window_samples, std::size_t& lags) {
    const auto m = js.cols();
    const std::size_t samples = outputs > 0 ? r.size() / outputs : 0;
    Eigen::MatrixXd g = Eigen::MatrixXd::Zero(m, static_cast<Eigen::Index>(samples));
    for (std::size_t t = 0; t < samples; ++t)
        for (std::size_t k = 0; k < outputs; ++k) {
            const auto row = static_cast<Eigen::Index>(t * outputs + k);
            g.col(static_cast<Eigen::Index>(t)) += js.row(row).transpose() * r[static_cast<std::size_t>(row)];
        }
    // Where each window's samples begin: no lag reaches across a window's start.
    std::vector<std::size_t> first;
    std::size_t at = 0;
    for (const std::size_t count : window_samples) {
        first.push_back(at);
        at += count;
    }
    first.push_back(samples);
    const auto same_window = [&](std::size_t t, std::size_t lag) {
        const auto it = std::upper_bound(first.begin(), first.end(), t);
        return t >= lag && t - lag >= *(it - 1);
    };
    // Andrews (1991): each score component as an AR(1), ρ_a and its innovation variance σ_a².
    double numerator = 0.0, denominator = 0.0;
    for (Eigen::Index a = 0; a < m; ++a) {
        double xy = 0.0, xx = 0.0;
        for (std::size_t t = 1; t < samples; ++t)
            if (same_window(t, 1)) {
                xy += g(a, static_cast<Eigen::Index>(t)) * g(a, static_cast<Eigen::Index>(t - 1));
                xx += g(a, static_cast<Eigen::Index>(t - 1)) * g(a, static_cast<Eigen::Index>(t - 1));
            }
        const double rho = xx > 0 ? std::clamp(xy / xx, -0.97, 0.97) : 0.0;
        double e2 = 0.0;
        std::size_t count = 0;
        for (std::size_t t = 1; t < samples; ++t)
            if (same_window(t, 1)) {
                const double e = g(a, static_cast<Eigen::Index>(t)) - rho * g(a, static_cast<Eigen::Index>(t - 1));
                e2 += e * e;
                ++count;
            }
        const double s4 = count > 0 ? (e2 / static_cast<double>(count)) * (e2 / static_cast<double>(count)) : 0.0;
        numerator += 4 * rho * rho * s4 / (std::pow(1 - rho, 6) * std::pow(1 + rho, 2));
        denominator += s4 / std::pow(1 - rho, 4);
    }
    const double alpha = denominator > 0 ? numerator / denominator : 0.0;
    lags = static_cast<std::size_t>(std::ceil(1.1447 * std::cbrt(alpha * static_cast<double>(samples))));
    lags = std::min(lags, samples / 4);
    // Coefficient by coefficient, never Eigen's threaded product: the same bits on any thread count.
    Eigen::MatrixXd s = g.lazyProduct(g.transpose());
    for (std::size_t l = 1; l <= lags; ++l) {
        const double weight = 1.0 - static_cast<double>(l) / static_cast<double>(lags + 1);
        Eigen::MatrixXd gamma = Eigen::MatrixXd::Zero(m, m);
        for (std::size_t t = l; t < samples; ++t)
            if (same_window(t, l))
                gamma += g.col(static_cast<Eigen::Index>(t)) * g.col(static_cast<Eigen::Index>(t - l)).transpose();
        s += weight * (gamma + gamma.transpose());
    }
    return s;
}

}  // namespace tvid

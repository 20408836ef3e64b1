#include "tvid/analysis/residual_whiteness.hpp"

#include <algorithm>
#include <boost/math/distributions/chi_squared.hpp>
#include <cmath>

namespace tvid {

namespace {

// The finite runs of each segment: a non-finite residual splits a window.
std::vector<std::vector<double>> finite_runs(const std::vector<std::vector<double>>& segments) {
    std::vector<std::vector<double>> runs;
    for (const std::vector<double>& s : segments) {
        std::vector<double> run;
        for (double e : s) {
            if (std::isfinite(e)) { run.push_back(e); continue; }
            if (!run.empty()) runs.push_back(std::move(run));
            run.clear();
        }
        if (!run.empty()) runs.push_back(std::move(run));
    }
    return runs;
}

}  // namespace

ResidualWhiteness assess_whiteness(const std::vector<std::vector<double>>& segments, int lags) {
    ResidualWhiteness w;
    const std::vector<std::vector<double>> runs = finite_runs(segments);
    std::size_t n = 0, longest = 0;
    double sum = 0.0, sum_sq = 0.0;
    for (const auto& r : runs) {
        n += r.size();
        longest = std::max(longest, r.size());
        for (double e : r) { sum += e; sum_sq += e * e; }
    }
    if (n < 8) return w;
    const double mean = sum / static_cast<double>(n);
    w.samples = n;
    w.rms = std::sqrt(sum_sq / static_cast<double>(n));
    w.lags = std::max(1, std::min(lags, static_cast<int>(longest / 3)));

    double variance_sum = 0.0, diff_sq = 0.0;
    std::size_t diffs = 0;
    std::vector<double> lagged(static_cast<std::size_t>(w.lags) + 1, 0.0);
    for (const auto& r : runs) {
        for (std::size_t i = 0; i < r.size(); ++i) {
            const double e = r[i] - mean;
            variance_sum += e * e;
            for (std::size_t k = 1; k < lagged.size() && i + k < r.size(); ++k) lagged[k] += e * (r[i + k] - mean);
            if (i + 1 < r.size()) {
                diff_sq += (r[i + 1] - r[i]) * (r[i + 1] - r[i]);
                ++diffs;
            }
        }
    }
    if (!(variance_sum > 0.0)) {  // a constant residual: nothing random in it at all
        w.lag1_correlation = 1.0;
        w.systematic_share = w.rms > 0 ? 1.0 : 0.0;
        w.p_value = w.rms > 0 ? 0.0 : 1.0;
        return w;
    }
    const double dn = static_cast<double>(n);
    for (std::size_t k = 1; k < lagged.size(); ++k) {
        const double rho = lagged[k] / variance_sum;
        if (k == 1) w.lag1_correlation = rho;
        w.ljung_box += rho * rho / (dn - static_cast<double>(k));
    }
    w.ljung_box *= dn * (dn + 2.0);
    const boost::math::chi_squared chi2(w.lags);
    w.p_value = boost::math::cdf(boost::math::complement(chi2, w.ljung_box));
    w.noise_rms = diffs > 0 ? std::sqrt(diff_sq / static_cast<double>(diffs) / 2.0) : 0.0;
    const double variance = variance_sum / dn;
    w.systematic_share = std::max(0.0, 1.0 - w.noise_rms * w.noise_rms / variance);
    return w;
}

}  // namespace tvid

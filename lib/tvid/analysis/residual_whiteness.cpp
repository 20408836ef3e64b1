#include "tvid/analysis/residual_whiteness.hpp"

#include <algorithm>
#include <boost/math/distributions/chi_squared.hpp>
#include <cmath>

#include "tvid/analysis/residual_correlation.hpp"

namespace tvid {

namespace {

// The one-step prediction error variance of the best AR(L) predictor over the variance,
// Π (1 − κ_k²), by the Levinson–Durbin recursion on ρ_0 = 1, ρ_1 … ρ_L.
double prediction_error_ratio(const std::vector<double>& rho) {
    const std::size_t order = rho.size() - 1;
    std::vector<double> a(order + 1, 0.0), previous(order + 1, 0.0);
    double error = 1.0;
    for (std::size_t k = 1; k <= order; ++k) {
        double acc = rho[k];
        for (std::size_t j = 1; j < k; ++j) acc -= a[j] * rho[k - j];
        const double kappa = error > 0 ? acc / error : 0.0;
        if (!(std::abs(kappa) < 1.0)) return 0.0;  // perfectly predictable (a pure tone, a trend)
        previous = a;
        a[k] = kappa;
        for (std::size_t j = 1; j < k; ++j) a[j] = previous[j] - kappa * previous[k - j];
        error *= 1.0 - kappa * kappa;
    }
    return error;
}

}  // namespace

ResidualWhiteness assess_whiteness(const std::vector<std::vector<double>>& segments, int lags) {
    ResidualWhiteness w;
    const std::vector<std::vector<double>> runs = finite_runs(segments);
    std::size_t n = 0, longest = 0;
    double sum_sq = 0.0;
    for (const auto& r : runs) {
        n += r.size();
        longest = std::max(longest, r.size());
        for (double e : r) sum_sq += e * e;
    }
    if (n < 8) return w;
    w.samples = n;
    w.rms = std::sqrt(sum_sq / static_cast<double>(n));
    w.lags = std::max(1, std::min(lags, static_cast<int>(longest / 3)));

    // ρ_0 … ρ_L as the residual analysis computes them (residual_correlation.hpp).
    const PooledAutocorrelation a = pooled_autocorrelation(runs, w.lags);
    if (!(a.sum_of_squares > 0.0)) {  // a constant residual: nothing random in it at all
        w.lag1_correlation = 1.0;
        w.systematic_share = w.rms > 0 ? 1.0 : 0.0;
        w.p_value = w.rms > 0 ? 0.0 : 1.0;
        return w;
    }
    const double dn = static_cast<double>(n);
    const std::vector<double>& rho = a.rho;
    for (std::size_t k = 1; k < rho.size(); ++k) w.ljung_box += rho[k] * rho[k] / (dn - static_cast<double>(k));
    w.lag1_correlation = rho[1];
    w.ljung_box *= dn * (dn + 2.0);
    const boost::math::chi_squared chi2(w.lags);
    w.p_value = boost::math::cdf(boost::math::complement(chi2, w.ljung_box));
    const double unpredictable = std::clamp(prediction_error_ratio(rho), 0.0, 1.0);
    w.systematic_share = 1.0 - unpredictable;
    w.noise_rms = std::sqrt(unpredictable * a.sum_of_squares / dn);
    return w;
}

}  // namespace tvid

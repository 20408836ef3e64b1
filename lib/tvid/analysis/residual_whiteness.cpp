#include "tvid/analysis/residual_whiteness.hpp"

#include <algorithm>
#include <boost/math/distributions/chi_squared.hpp>
#include <cmath>

#include "tvid/analysis/residual_correlation.hpp"

namespace tvid {

namespace {

// The best AR(L) predictor of a sequence of auto-covariance (or autocorrelation) r_0 … r_L,
// by the Levinson–Durbin recursion: its coefficients a_1 … a_L (a_0 unused) and the ratio of
// its one-step prediction error variance to r_0, Π (1 − κ_k²). A perfectly predictable
// sequence (a pure tone, a trend) stops the recursion with ratio 0.
struct ArPredictor {
    std::vector<double> a;
    double error_ratio = 1.0;
};

ArPredictor levinson_durbin(const std::vector<double>& r) {
    const std::size_t order = r.size() - 1;
    ArPredictor p;
    p.a.assign(order + 1, 0.0);
    std::vector<double> previous(order + 1, 0.0);
    if (!(r[0] > 0)) return p;
    double error = r[0];
    for (std::size_t k = 1; k <= order; ++k) {
        double acc = r[k];
        for (std::size_t j = 1; j < k; ++j) acc -= p.a[j] * r[k - j];
        const double kappa = error > 0 ? acc / error : 0.0;
        if (!(std::abs(kappa) < 1.0)) {
            p.error_ratio = 0.0;
            return p;
        }
        previous = p.a;
        p.a[k] = kappa;
        for (std::size_t j = 1; j < k; ++j) p.a[j] = previous[j] - kappa * previous[k - j];
        error *= 1.0 - kappa * kappa;
    }
    p.error_ratio = error / r[0];
    return p;
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
    const double unpredictable = std::clamp(levinson_durbin(rho).error_ratio, 0.0, 1.0);
    w.systematic_share = 1.0 - unpredictable;
    w.noise_rms = std::sqrt(unpredictable * a.sum_of_squares / dn);
    return w;
}

ResidualWhiteness assess_whiteness_against(const std::vector<std::vector<double>>& segments,
                                           const std::vector<double>& coloured, int lags) {
    if (coloured.empty() || !(coloured[0] > 0)) return assess_whiteness(segments, lags);
    std::vector<std::vector<double>> runs = finite_runs(segments);
    std::size_t n = 0;
    double sum = 0.0, sum_sq = 0.0;
    for (const auto& r : runs) {
        n += r.size();
        for (double e : r) sum += e;
    }
    if (n < 8) return assess_whiteness(segments, lags);
    const double mean = sum / static_cast<double>(n);
    for (auto& r : runs)
        for (double& e : r) {
            e -= mean;
            sum_sq += e * e;
        }
    const double variance = sum_sq / static_cast<double>(n);
    // The noise model's auto-covariance: white measurement noise plus the coloured part at the
    // level the residual's own lags 1 … K show (α, within kNoiseLevelRange of the declared): the
    // level of a declared noise is known to some tens of per cent, and one recording's
    // coloured noise differs from its expectation by as much.
    const std::size_t order = std::min<std::size_t>(coloured.size() - 1, kWhiteningOrder);
    const PooledAutocorrelation lagged = pooled_autocorrelation(runs, static_cast<int>(order));
    double fit_sum = 0.0, norm = 0.0;
    for (std::size_t l = 1; l <= order && l < lagged.rho.size(); ++l) {
        fit_sum += lagged.rho[l] * variance * coloured[l];
        norm += coloured[l] * coloured[l];
    }
    const double level = norm > 0 ? std::clamp(fit_sum / norm, 1.0 / kNoiseLevelRange, kNoiseLevelRange) : 1.0;
    std::vector<double> model(order + 1);
    for (std::size_t l = 0; l <= order; ++l) model[l] = level * coloured[l];
    model[0] = std::max(variance, model[0] + kWhiteShareFloor * variance);
    const ArPredictor filter = levinson_durbin(model);
    std::vector<std::vector<double>> filtered;
    for (const auto& r : runs) {
        if (r.size() <= order) continue;
        std::vector<double> f(r.size() - order);
        for (std::size_t t = order; t < r.size(); ++t) {
            double v = r[t];
            for (std::size_t j = 1; j <= order; ++j) v -= filter.a[j] * r[t - j];
            f[t - order] = v;
        }
        filtered.push_back(std::move(f));
    }
    ResidualWhiteness w = assess_whiteness(filtered, lags);
    if (w.samples == 0) return assess_whiteness(segments, lags);
    // The share: what the residual's own AR(L) predicts beyond what the same predictor of the
    // noise model predicts of it. A difference of two predictable variances, robust where the
    // white part is small and the whitening filter's gain large.
    const ResidualWhiteness own = assess_whiteness(runs, lags);
    const std::size_t l = static_cast<std::size_t>(std::min<int>(own.lags, static_cast<int>(order)));
    const std::vector<double> head(model.begin(), model.begin() + static_cast<std::ptrdiff_t>(l + 1));
    const double model_predictable = (1.0 - std::clamp(levinson_durbin(head).error_ratio, 0.0, 1.0)) * model[0];
    w.systematic_share = std::clamp((own.systematic_share * variance - model_predictable) / variance, 0.0, 1.0);
    w.rms = std::sqrt(variance + mean * mean);
    w.noise_rms = std::sqrt((1.0 - w.systematic_share) * variance);
    w.propagated_noise_rms = std::sqrt(coloured[0]);
    w.propagated_noise_level = level;
    return w;
}

}  // namespace tvid

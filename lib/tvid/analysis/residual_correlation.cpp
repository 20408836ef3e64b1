#include "tvid/analysis/residual_correlation.hpp"

#include <algorithm>
#include <cmath>

namespace tvid {

namespace {

constexpr std::size_t kCorrelationMinimumSamples = 8;

// Pairs (u_i, e_i) of each window, split where either is not finite.
void paired_runs(const std::vector<std::vector<double>>& u, const std::vector<std::vector<double>>& e,
                 std::vector<std::vector<double>>& u_runs, std::vector<std::vector<double>>& e_runs) {
    for (std::size_t w = 0; w < u.size() && w < e.size(); ++w) {
        std::vector<double> ru, re;
        const std::size_t n = std::min(u[w].size(), e[w].size());
        for (std::size_t i = 0; i < n; ++i) {
            if (std::isfinite(u[w][i]) && std::isfinite(e[w][i])) {
                ru.push_back(u[w][i]);
                re.push_back(e[w][i]);
                continue;
            }
            if (!ru.empty()) {
                u_runs.push_back(std::move(ru));
                e_runs.push_back(std::move(re));
            }
            ru.clear();
            re.clear();
        }
        if (!ru.empty()) {
            u_runs.push_back(std::move(ru));
            e_runs.push_back(std::move(re));
        }
    }
}

void mark_outside(CorrelationTest& t, bool skip_zero) {
    for (std::size_t i = 0; i < t.lags.size(); ++i) {
        if (skip_zero && t.lags[i] == 0) continue;
        const double expected = i < t.expected.size() ? t.expected[i] : 0.0;
        if (std::abs(t.values[i] - expected) > t.band) t.outside.push_back(t.lags[i]);
    }
}

}  // namespace

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

PooledAutocorrelation pooled_autocorrelation(const std::vector<std::vector<double>>& runs, int lags) {
    PooledAutocorrelation a;
    double sum = 0.0;
    for (const auto& r : runs) {
        a.samples += r.size();
        for (double e : r) sum += e;
    }
    const std::size_t count = static_cast<std::size_t>(std::max(0, lags)) + 1;
    a.rho.assign(count, 0.0);
    a.rho[0] = 1.0;
    if (a.samples == 0) return a;
    a.mean = sum / static_cast<double>(a.samples);
    std::vector<double> lagged(count, 0.0);
    for (const auto& r : runs) {
        for (std::size_t i = 0; i < r.size(); ++i) {
            const double e = r[i] - a.mean;
            a.sum_of_squares += e * e;
            for (std::size_t k = 1; k < count && i + k < r.size(); ++k) lagged[k] += e * (r[i + k] - a.mean);
        }
    }
    if (a.sum_of_squares > 0.0)
        for (std::size_t k = 1; k < count; ++k) a.rho[k] = lagged[k] / a.sum_of_squares;
    return a;
}

int CorrelationTest::tested(int from) const {
    int n = 0;
    for (int lag : lags) n += lag >= from && !(lag == 0 && lags.front() == 0) ? 1 : 0;
    return n;
}

int CorrelationTest::outside_from(int from) const {
    return static_cast<int>(std::count_if(outside.begin(), outside.end(), [from](int lag) { return lag >= from; }));
}

CorrelationTest autocorrelation_test(const std::vector<std::vector<double>>& runs, int lags) {
    CorrelationTest t;
    const PooledAutocorrelation a = pooled_autocorrelation(runs, lags);
    t.samples = a.samples;
    if (a.samples < kCorrelationMinimumSamples) return t;
    t.available = true;
    for (int k = 0; k <= lags; ++k) {
        t.lags.push_back(k);
        t.values.push_back(a.rho[static_cast<std::size_t>(k)]);
    }
    t.band = kCorrelationZ / std::sqrt(static_cast<double>(a.samples));
    mark_outside(t, true);
    return t;
}

CorrelationTest cross_correlation_test(const std::vector<std::vector<double>>& u,
                                       const std::vector<std::vector<double>>& e, int lags,
                                       const std::vector<double>& noise_covariance, int band_lags) {
    CorrelationTest t;
    std::vector<std::vector<double>> u_runs, e_runs;
    paired_runs(u, e, u_runs, e_runs);
    std::size_t longest = 0;
    for (const auto& r : u_runs) longest = std::max(longest, r.size());
    const int p_lags = std::max(lags, std::min(band_lags, static_cast<int>(longest / 4)));
    const PooledAutocorrelation au = pooled_autocorrelation(u_runs, p_lags);
    const PooledAutocorrelation ae = pooled_autocorrelation(e_runs, p_lags);
    t.samples = au.samples;
    if (au.samples < kCorrelationMinimumSamples) return t;
    t.available = true;
    const double norm = std::sqrt(au.sum_of_squares * ae.sum_of_squares);
    for (int tau = -lags; tau <= lags; ++tau) {
        double sum = 0.0;
        for (std::size_t r = 0; r < u_runs.size(); ++r) {
            const std::vector<double>& ur = u_runs[r];
            const std::vector<double>& er = e_runs[r];
            const std::size_t n = ur.size(), shift = static_cast<std::size_t>(std::abs(tau));
            for (std::size_t i = 0; i + shift < n; ++i)  // u_i with e_{i+τ}: τ ≥ 0 reads e ahead, τ < 0 u ahead
                sum += tau >= 0 ? (ur[i] - au.mean) * (er[i + shift] - ae.mean)
                                : (ur[i + shift] - au.mean) * (er[i] - ae.mean);
        }
        t.lags.push_back(tau);
        t.values.push_back(norm > 0.0 ? sum / norm : 0.0);  // a constant input or residual: no correlation
        if (noise_covariance.empty()) continue;
        const auto k = static_cast<std::size_t>(std::abs(tau));
        double pairs = 0.0;
        for (const std::vector<double>& ur : u_runs) pairs += ur.size() > k ? static_cast<double>(ur.size() - k) : 0.0;
        t.expected.push_back(tau >= 0 && k < noise_covariance.size() && norm > 0.0 ? -pairs * noise_covariance[k] / norm : 0.0);
    }
    // Ljung's P over the pair's own autocorrelations: with Bartlett weights over the M lags;
    // over a longer memory (band_lags) with weight 1, as Bartlett's formula sums them, so that
    // a slowly wandering pair is not cut short.
    double p = 1.0;
    for (int k = 1; k <= p_lags; ++k)
        p += 2.0 * (p_lags > lags ? 1.0 : 1.0 - static_cast<double>(k) / (p_lags + 1)) *
             au.rho[static_cast<std::size_t>(k)] * ae.rho[static_cast<std::size_t>(k)];
    t.variance_factor = std::max(1.0, p);
    t.band = kCorrelationZ * std::sqrt(t.variance_factor / static_cast<double>(au.samples));
    mark_outside(t, false);
    return t;
}

ResidualCorrelation analyse_residual_correlation(const std::vector<std::vector<std::vector<double>>>& residuals,
                                                 const std::vector<std::vector<std::vector<double>>>& inputs,
                                                 int lags,
                                                 const std::vector<std::vector<std::vector<double>>>& noise_covariance,
                                                 const std::vector<int>& band_lags) {
    ResidualCorrelation out;
    std::size_t longest = 0;
    std::vector<std::vector<std::vector<double>>> runs;
    for (const auto& windows : residuals) {
        runs.push_back(finite_runs(windows));
        for (const auto& r : runs.back()) longest = std::max(longest, r.size());
    }
    out.lags = std::max(1, std::min(lags, static_cast<int>(longest / 3)));
    for (const auto& r : runs) out.autocorrelation.push_back(autocorrelation_test(r, out.lags));
    for (std::size_t q = 0; q < inputs.size(); ++q) {
        out.cross_correlation.emplace_back();
        for (std::size_t k = 0; k < residuals.size(); ++k) {
            const bool noisy = q < noise_covariance.size() && k < noise_covariance[q].size();
            out.cross_correlation.back().push_back(
                cross_correlation_test(inputs[q], residuals[k], out.lags, noisy ? noise_covariance[q][k] : std::vector<double>{},
                                       k < band_lags.size() ? band_lags[k] : 0));
        }
    }
    return out;
}

}  // namespace tvid

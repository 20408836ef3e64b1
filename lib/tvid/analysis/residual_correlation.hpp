#pragma once
// The residual analysis of the System Identification Toolbox's resid(): the autocorrelation
// of each output's residual and the cross-correlation of each input with it, over the
// windows of a split (each a contiguous stretch of samples; no lag crosses a window's end),
// with 99 % confidence bands. With e the residual and u an input, each less its mean over
// the split's samples, N the samples, M the lags:
//   ρ_e(k) = Σ e_i e_{i+k} / Σ e_i²                       k = 0 … M
//   r(τ)   = Σ u_i e_{i+τ} / sqrt(Σ u_i² · Σ e_i²)          τ = −M … M
// τ > 0: the residual τ samples after the input (what past inputs leave in the residual: a
// dynamic from u that the model misses); τ < 0: the residual before the input (feedback).
// Bands, z = 2.576 (two-sided 99 % of the normal distribution):
//   ACF: ±z/√N, the band of a white residual (k ≥ 1);
//   CCF: ±z·sqrt(P/N), P = max(1, Σ_{|k|≤M} (1 − |k|/(M+1)) ρ_e(k) ρ_u(k)), the band of a
//        residual independent of the input (Ljung, System Identification, 2nd ed., §16.6:
//        √N·r(τ) → N(0, P) for a coloured residual and input alike; the Bartlett weights keep
//        the estimate of P positive). P = 1, i.e. ±z/√N, when either is white; it is never
//        taken below 1, so the band is never narrower than the white residual's.
// Lag k of a white residual lies outside its band with probability 1 %.

#include <cstddef>
#include <vector>

namespace tvid {

/// The largest lag M (MATLAB resid's default); fewer when the longest window is shorter
/// than 3·M samples (a third of it).
constexpr int kCorrelationLags = 25;
/// The bands' confidence, and its two-sided normal point z.
constexpr double kCorrelationConfidence = 0.99;
constexpr double kCorrelationZ = 2.5758293035489004;

/// The finite runs of each segment: a non-finite value ends a run.
std::vector<std::vector<double>> finite_runs(const std::vector<std::vector<double>>& segments);

/// ρ_0 … ρ_L of `runs`, pooled: the mean over every sample is removed, and the lagged
/// products are summed within each run only.
struct PooledAutocorrelation {
    std::size_t samples = 0;      ///< N
    double mean = 0.0;
    double sum_of_squares = 0.0;  ///< Σ (e − mean)²; 0 for a constant signal, whose ρ_k (k ≥ 1) are then 0
    std::vector<double> rho;      ///< ρ_0 = 1, ρ_1 … ρ_L (the biased estimate: a positive definite sequence)
};
PooledAutocorrelation pooled_autocorrelation(const std::vector<std::vector<double>>& runs, int lags);

/// One correlation function with its band.
struct CorrelationTest {
    bool available = false;        ///< false below 8 samples
    std::size_t samples = 0;       ///< N
    std::vector<int> lags;         ///< 0 … M (autocorrelation) or −M … M (cross-correlation)
    std::vector<double> values;    ///< at each lag
    double band = 0.0;             ///< the 99 % band ±band
    double variance_factor = 1.0;  ///< P of the cross-correlation's band (1 for the autocorrelation)
    /// A cross-correlation's value that a declared noise on the input leaves at each lag at the
    /// true parameters (cross_correlation_test's `expected`); empty when none. A lag is
    /// tested by its distance from it.
    std::vector<double> expected;
    std::vector<int> outside;      ///< the lags whose |value − expected| > band (lag 0 of an autocorrelation is not tested)

    /// The lags tested (lag 0 of an autocorrelation left out), and how many of those lie
    /// outside the band, among the lags from `from` on.
    int tested(int from) const;
    int outside_from(int from) const;
};

/// A split's residual analysis.
struct ResidualCorrelation {
    int lags = 0;                                 ///< M
    std::vector<CorrelationTest> autocorrelation;  ///< per output
    std::vector<std::vector<CorrelationTest>> cross_correlation;  ///< [input][output]
};

/// `residuals[output][window]` and `inputs[input][window]`: each output's residual and each
/// input at the scored samples of each window (the same windows and lengths throughout).
/// A non-finite value ends a run (for a cross-correlation, a non-finite input or residual).
/// `noise_covariance[input][output]` and `band_lags[output]`: cross_correlation_test's, or
/// empty (no declared noise).
ResidualCorrelation analyse_residual_correlation(const std::vector<std::vector<std::vector<double>>>& residuals,
                                                 const std::vector<std::vector<std::vector<double>>>& inputs,
                                                 int lags = kCorrelationLags,
                                                 const std::vector<std::vector<std::vector<double>>>& noise_covariance = {},
                                                 const std::vector<int>& band_lags = {});

/// The autocorrelation test of one residual alone (its runs as finite_runs gives them).
CorrelationTest autocorrelation_test(const std::vector<std::vector<double>>& runs, int lags);

/// The cross-correlation test of input u with residual e, window by window (equal lengths).
/// `noise_covariance` (τ = 0 … M, or empty): E[n(t) δ(t + τ)] of the input's declared noise n
/// and what it carries to the output, δ (analysis/input_noise.hpp). The simulation reads u + n
/// where the line felt u, so the residual holds −δ, and r(τ) is expected at
/// −Σ_runs (N_run − τ) E[n δ](τ) / sqrt(Σu² Σe²) (0 for τ < 0: noise does not run backwards).
/// `band_lags` (≥ lags, at most a quarter of the longest run): the lags of P's sum, for a
/// residual whose memory is known to reach further than M (a declared input noise carried
/// through a slow mode: a residual and an input that both wander correlate by chance far
/// beyond the white band).
CorrelationTest cross_correlation_test(const std::vector<std::vector<double>>& u,
                                       const std::vector<std::vector<double>>& e, int lags,
                                       const std::vector<double>& noise_covariance = {}, int band_lags = 0);

}  // namespace tvid

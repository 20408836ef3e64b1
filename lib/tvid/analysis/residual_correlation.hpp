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
    std::vector<int> outside;      ///< the lags whose |value| > band (lag 0 of an autocorrelation is not tested)

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
ResidualCorrelation analyse_residual_correlation(const std::vector<std::vector<std::vector<double>>>& residuals,
                                                 const std::vector<std::vector<std::vector<double>>>& inputs,
                                                 int lags = kCorrelationLags);

/// The autocorrelation test of one residual alone (its runs as finite_runs gives them).
CorrelationTest autocorrelation_test(const std::vector<std::vector<double>>& runs, int lags);

/// The cross-correlation test of input u with residual e, window by window (equal lengths).
CorrelationTest cross_correlation_test(const std::vector<std::vector<double>>& u,
                                       const std::vector<std::vector<double>>& e, int lags);

}  // namespace tvid

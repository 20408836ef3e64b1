#pragma once
// Is a residual noise, or a misfit the model leaves? Per output, over the windows (each a
// contiguous stretch of samples; no lag crosses a window boundary):
//   ρ_k   = Σ e_i e_{i+k} / Σ e_i²                 (normalised autocorrelation, e mean-free:
//                                                  the residual analysis's, residual_correlation.hpp)
//   Q     = N (N+2) Σ_{k=1..L} ρ_k² / (N − k)      (Ljung & Box 1978), χ²(L) when e is white
//   share = 1 − Π_{k=1..L} (1 − κ_k²)             (the share of the residual variance that its
//                                                  own past L samples predict: κ_k are the
//                                                  reflection coefficients of the Levinson–Durbin
//                                                  recursion on ρ_0 … ρ_L, the AR(L) predictor)
//   σ_n   = sqrt((1 − share) · var e)              (what no predictor removes: the noise)
// A misfit slow against the sampling (a missed resonance, a wrong stiffness) and one near
// the Nyquist frequency (a missed mode above the model's) are both predictable; noise is
// not. A fit at the noise floor has share ≈ L/N and a large p-value; a fit at RMSE 0.35 on
// noise 0.10 has share ≈ 0.91.

#include <cstddef>
#include <vector>

namespace tvid {

/// The lags of the Ljung–Box statistic (fewer when a window is short).
constexpr int kLjungBoxLags = 20;

struct ResidualWhiteness {
    std::size_t samples = 0;       ///< N (finite residuals)
    int lags = 0;                  ///< L
    double rms = 0.0;              ///< of e, mean included
    double lag1_correlation = 0.0; ///< ρ_1
    double ljung_box = 0.0;        ///< Q
    double p_value = 1.0;          ///< P(χ²(L) > Q)
    double noise_rms = 0.0;        ///< σ_n: the residual's unpredictable part
    double systematic_share = 0.0; ///< of the residual variance: what an AR(L) predictor explains
    /// Against a noise model (assess_whiteness_against): the standard deviation of its coloured
    /// part, the declared input noise carried to this output; 0 when none.
    double propagated_noise_rms = 0.0;
    /// And the level α at which the residual's lags hold it (1: as declared).
    double propagated_noise_level = 1.0;
};

/// `segments`: one output's residuals, one contiguous stretch per window. Non-finite values
/// end a stretch. Fewer than 3·L samples: lags shrink; fewer than 8 samples: nothing assessed
/// (samples = 0).
ResidualWhiteness assess_whiteness(const std::vector<std::vector<double>>& segments, int lags = kLjungBoxLags);

/// The largest order of the noise model's whitening filter (assess_whiteness_against).
constexpr int kWhiteningOrder = 40;
/// The white part's variance is at least this share of the residual's (assess_whiteness_against).
constexpr double kWhiteShareFloor = 0.01;
/// The coloured part's level is taken within [1/k, k] of the declared one (assess_whiteness_against).
constexpr double kNoiseLevelRange = 2.0;

/// The same test against a noise model: the residual of a right model is white measurement
/// noise of variance σ_m² plus a known coloured noise of auto-covariance c_0 … c_K
/// (`coloured`: the declared input noise carried to this output, analysis/input_noise.hpp) at
/// a level α: the least-squares fit of α c_l to the residual's auto-covariance at lags
/// 1 … K (K = min(K, kWhiteningOrder)), within [1/kNoiseLevelRange, kNoiseLevelRange], and
/// σ_m² = var e − α c_0 (at least kWhiteShareFloor · var e). Each run is filtered by that noise
/// model's one-step prediction-error filter of order K (Levinson–Durbin on σ_m² δ_l + α c_l),
/// which turns such noise white, and the filtered runs are assessed as above for p_value,
/// ljung_box and lag1_correlation. systematic_share is what the residual's own AR(L) predicts
/// of it beyond what the same predictor of the noise model predicts, over var e (a difference
/// of predictable variances: robust where the white part is small and the filter's gain
/// large). rms stays the residual's, noise_rms is √((1 − share) var e), propagated_noise_rms
/// √c_0, propagated_noise_level α. A misfit keeps its structure through the filter and adds
/// to the predictable variance. A level below 1 need not mean an overstated noise: at a fit's
/// optimum the parameters take up part of a noise of long memory. An empty `coloured`:
/// assess_whiteness.
ResidualWhiteness assess_whiteness_against(const std::vector<std::vector<double>>& segments,
                                           const std::vector<double>& coloured, int lags = kLjungBoxLags);

}  // namespace tvid

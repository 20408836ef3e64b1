#pragma once
// Is a residual noise, or a misfit the model leaves? Per output, over the windows (each a
// contiguous stretch of samples; no lag crosses a window boundary):
//   ρ_k   = Σ e_i e_{i+k} / Σ e_i²                 (normalised autocorrelation, e mean-free)
//   Q     = N (N+2) Σ_{k=1..L} ρ_k² / (N − k)      (Ljung & Box 1978), χ²(L) when e is white
//   σ_n   = sqrt(mean (e_{i+1} − e_i)² / 2)        (the sample-to-sample noise: white noise
//                                                  of variance σ² has mean Δe² = 2σ²; a misfit
//                                                  slow against the sampling adds almost nothing)
//   share = max(0, 1 − σ_n² / var e)               (the share of the residual variance that is
//                                                  systematic; ≈ ρ_1)
// A fit at the noise floor has share ≈ 0 and a large p-value; a fit at RMSE 0.35 on noise
// 0.10 has share ≈ 0.92.

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
    double noise_rms = 0.0;        ///< σ_n
    double systematic_share = 0.0; ///< of the residual variance
};

/// `segments`: one output's residuals, one contiguous stretch per window. Non-finite values
/// end a stretch. Fewer than 3·L samples: lags shrink; fewer than 8 samples: nothing assessed
/// (samples = 0).
ResidualWhiteness assess_whiteness(const std::vector<std::vector<double>>& segments, int lags = kLjungBoxLags);

}  // namespace tvid

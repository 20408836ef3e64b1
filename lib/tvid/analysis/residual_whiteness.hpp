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
};

/// `segments`: one output's residuals, one contiguous stretch per window. Non-finite values
/// end a stretch. Fewer than 3·L samples: lags shrink; fewer than 8 samples: nothing assessed
/// (samples = 0).
ResidualWhiteness assess_whiteness(const std::vector<std::vector<double>>& segments, int lags = kLjungBoxLags);

}  // namespace tvid

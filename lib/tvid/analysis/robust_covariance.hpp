#pragma once
// The long-run covariance of least-squares scores for standard errors that hold when the
// residuals are correlated in time (Newey & West 1987, with Andrews' 1991 bandwidth): the
// middle of the sandwich (JᵀJ)⁻¹ S (JᵀJ)⁻¹ (analysis/uncertainty.hpp).

#include <Eigen/Core>
#include <cstddef>
#include <vector>

namespace tvid {

/// S = Σ_t g_t g_tᵀ + Σ_{l=1..L} (1 − l/(L+1)) Σ_t (g_t g_{t−l}ᵀ + g_{t−l} g_tᵀ), with the scores
/// g_t = Σ_k js(tK + k)ᵀ r(tK + k): row tK + k of the Jacobian js and the residuals r is output k
/// of scored sample t (K = `outputs`, the outputs of one sample together). The samples run
/// window after window (window_samples: each window's count); no lag reaches across a window's
/// start. L (`lags`, set here) by Andrews' AR(1) plug-in rule for the Bartlett kernel,
/// 1.1447·(α·T)^(1/3), α from each score component's AR(1) fit, at most T/4.
Eigen::MatrixXd long_run_score_covariance(const Eigen::MatrixXd& js, const std::vector<double>& r, std::size_t outputs,
                                          const std::vector<std::size_t>& window_samples, std::size_t& lags);

}  // namespace tvid

#pragma once
// Quality of a simulated output against its measurement:
//   E      = mean |y* − y|                      (Yoshida & Takamatsu eq. 19, the l1 cost)
//   E0     = mean |y − offset|                  (eq. 21, offset = the fitted amplitude shift)
//   Q      = (1 − E/E0)·100 %                   (eq. 20)
//   fit    = 100 (1 − ‖y − y*‖ / ‖y − ȳ‖) %     (normalized RMS fit)
//   RMSE   = sqrt(mean (y − y*)²)
//   r_i    = (y_i − y*_i) / y_i                 (the methodology paper Fig. 2b), and max |r_i|

#include <cstddef>
#include <vector>

namespace tvid {

struct FitMetrics {
    std::size_t samples = 0;
    double mean_abs_error = 0.0;   ///< E
    double sum_sq_error = 0.0;     ///< Σ e² (the l2 cost)
    double rmse = 0.0;
    double e0 = 0.0;
    double q_index = 0.0;          ///< %
    double fit_percent = 0.0;      ///< %
    double max_abs_residual_ratio = 0.0;  ///< max |r_i| over samples with y_i ≠ 0 (fraction, not %)
};

/// Residual ratio of one sample; NaN when the measurement is exactly zero.
double residual_ratio(double measured, double simulated);

FitMetrics compute_fit_metrics(const std::vector<double>& measured, const std::vector<double>& simulated,
                               double offset);

}  // namespace tvid

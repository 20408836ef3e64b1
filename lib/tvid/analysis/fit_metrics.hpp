#pragma once
// Quality of a simulated output against its measurement:
//   E      = mean |y* − y|                      (Yoshida & Takamatsu eq. 19, the l1 cost)
//   E0     = mean |y − offset|                  (eq. 21, offset = the fitted amplitude shift)
//   Q      = (1 − E/E0)·100 %                   (eq. 20)
//   fit    = 100 (1 − ‖y − y*‖ / ‖y − ȳ‖) %     (normalized RMS fit)
//   RMSE   = sqrt(mean (y − y*)²)
//   r_i    = (y_i − y*_i) / y_i                 (the methodology paper Fig. 2b), and max |r_i|
//            over the samples with |y_i| ≥ 10 % of the largest |y| of their window
// The methodology paper plots r_i at every sample of an engine speed near 130 rad/s, which
// never comes near zero, and gives no rule for a signal that does: there r_i has a pole at
// every zero crossing (a torque's max |r_i| of 7494 % says nothing about the fit). So r_i
// counts only where the measured value is at least kResidualRatioFloor of its window's
// largest magnitude: on the paper's signal that leaves out no sample, and the figure is
// the paper's. A split's pooled value is the largest of its windows'. The terminal,
// summary.json, estimation.csv (the cell is empty below the floor), the plots, batch.csv
// and `tvid check` all read this one figure.

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
    double max_abs_residual_ratio = 0.0;  ///< max |r_i| over samples with |y_i| ≥ the floor (fraction, not %)
    /// The smallest |y_i| the ratio counts (output unit; at least the window's floor, below):
    /// the scale over which the noise moves the ratio most. Pooled: the smallest of the windows'.
    double residual_ratio_min_abs_y = 0.0;
};

/// A sample's residual ratio counts where |y| is at least this share of the largest |y| of its window.
constexpr double kResidualRatioFloor = 0.10;

/// kResidualRatioFloor · max |y| over `measured` (its finite values): the floor of a window.
double residual_ratio_floor(const std::vector<double>& measured);

/// Residual ratio of one sample; NaN when |measured| is below `floor` or exactly zero.
double residual_ratio(double measured, double simulated, double floor = 0.0);

/// The metrics of one window's samples (the residual ratio against that window's floor).
FitMetrics compute_fit_metrics(const std::vector<double>& measured, const std::vector<double>& simulated,
                               double offset);

}  // namespace tvid

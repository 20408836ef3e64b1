#pragma once
// Statistics of one quantity over the jobs of a batch: its spread (mean, standard
// deviation, coefficient of variation) and the robust z-score that flags outlying jobs
// (Iglewicz & Hoaglin, "How to Detect and Handle Outliers", 1993: the modified z-score
// M = 0.6745·(x − median)/MAD, an outlier when |M| > 3.5).

#include <cstddef>
#include <vector>

namespace tvid {

/// |M| above this marks an outlier (Iglewicz & Hoaglin's recommendation).
inline constexpr double kOutlierRobustZ = 3.5;
/// Fewer values than this judge no job: with three, the MAD is the smaller of the two outer
/// deviations, and the larger one's score is their ratio, however ordinary both are.
inline constexpr std::size_t kOutlierMinimumJobs = 5;
/// 0.6745 = Φ⁻¹(0.75): for normal data, MAD/0.6745 estimates the standard deviation,
/// so M is on the scale of an ordinary z-score.
inline constexpr double kRobustZFactor = 0.6745;

/// The median of the finite values; NaN when there is none.
double median(std::vector<double> values);

/// The median absolute deviation from the median, median(|x − median(x)|), over the
/// finite values (not rescaled); NaN when there is none.
double median_absolute_deviation(const std::vector<double>& values);

/// The modified z-score of each value, 0.6745·(x − median)/MAD, with the median and MAD of
/// the finite values. NaN for a value that is not finite, and for every value when the MAD
/// is 0 or undefined (more than half the values are equal: no scale to judge the rest by).
std::vector<double> robust_z_scores(const std::vector<double>& values);

/// The spread of one quantity over the jobs (finite values only).
struct Stability {
    std::size_t count = 0;
    double mean = 0.0;     ///< NaN when count = 0
    double std_dev = 0.0;  ///< sample standard deviation (n − 1); NaN when count < 2
    double cv = 0.0;       ///< std_dev / |mean|; NaN when std_dev is NaN or mean = 0
    double median = 0.0, mad = 0.0;  ///< NaN when count = 0
    double min = 0.0, max = 0.0;     ///< NaN when count = 0
};

Stability stability(const std::vector<double>& values);

}  // namespace tvid

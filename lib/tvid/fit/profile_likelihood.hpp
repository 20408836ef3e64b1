#pragma once
// The profile likelihood of one parameter: on a grid of its values, the other free
// parameters are fitted again (Levenberg–Marquardt from the optimum) with it held, and
//   Δχ²(v) = (S(v) − S(θ̂)) / s²,   s² = S(θ̂) / (N − M),   S = Σ e²
// is read against χ²₁ at 0.95 (3.841). Where Δχ² crosses it is the 95 % profile interval:
// honest for a parameter the linearised interval describes badly (a weak, nonlinear or
// bounded one), and open on a side where the grid never reaches the threshold. For a
// model linear in its parameters Δχ² is the exact parabola (v − θ̂)² / se², and the
// interval is θ̂ ± 1.96 se.
//
// The points run in parallel, each with its own problem on one thread; a point's result
// depends on its value alone, so the profile is the same for any thread count.

#include <atomic>
#include <optional>
#include <string>
#include <vector>

#include "tvid/experiment/experiment.hpp"
#include "tvid/optim/levenberg_marquardt.hpp"

namespace tvid {

/// χ²₁ at 0.95: the threshold of a 95 % profile interval.
constexpr double kProfileThreshold95 = 3.841458820694124;

struct ProfileOptions {
    std::string parameter;              ///< a free parameter of the experiment
    int points = 21;                    ///< grid points (odd counts put one on the optimum)
    std::optional<double> from, to;     ///< the grid's ends; default: θ̂ ∓ 4 standard errors within the bounds
    int threads = 0;                    ///< <= 0: all cores
    const std::atomic<bool>* stop = nullptr;
};

struct ProfilePoint {
    double value = 0.0;
    double cost = 0.0;                  ///< S: Σ e² with the others refitted (+inf when it failed)
    double delta_chi2 = 0.0;            ///< (S − S(θ̂)) / s²
    std::vector<double> others;         ///< the other free parameters there, in free-parameter order
    std::string termination;
    bool converged = false;
};

struct ProfileResult {
    std::string parameter;
    std::string unit;                   ///< its SI unit (model/parameter_units.hpp)
    std::vector<std::string> others;    ///< names of the other free parameters
    std::vector<double> optimum;        ///< the free parameters at θ̂
    double best_value = 0.0;            ///< θ̂ of the profiled parameter
    double best_cost = 0.0;             ///< S(θ̂)
    std::size_t residuals = 0;          ///< N
    double s2 = 0.0;
    double std_error = 0.0;             ///< the linearised one at θ̂ (NaN when undetermined)
    std::string optimum_termination;    ///< how the fit to θ̂ ended
    std::vector<ProfilePoint> points;   ///< in increasing value
    /// The 95 % profile interval: the outermost values where Δχ² crosses the threshold
    /// (interpolated between grid points); empty on a side where the grid's end is still
    /// below it (at a bound: the interval reaches the bound).
    std::optional<double> low, high;
    /// A grid point above the threshold inside the interval: the acceptable values form
    /// more than one valley (another local optimum), and the interval is their hull.
    bool disconnected = false;
    /// The lowest cost on the grid below S(θ̂): the fit to θ̂ was not the optimum.
    bool better_point_found = false;
    double seconds = 0.0;
    int threads = 1;
};

/// Throws InputError when the request cannot be profiled: the cost is not l2, the
/// parameter is not a free parameter of the experiment, or fewer than 3 points (the checks
/// profile_likelihood makes first, for a command to make before it claims its folder).
void check_profile_request(const Experiment& experiment, const ProfileOptions& options);

/// Fits the experiment by Levenberg–Marquardt from `start` (full parameter vector) to θ̂,
/// then profiles. Throws InputError when the parameter is not free, the cost is not l2,
/// or the grid is unusable.
ProfileResult profile_likelihood(const Experiment& experiment, const std::vector<double>& start,
                                 const ProfileOptions& options);

}  // namespace tvid

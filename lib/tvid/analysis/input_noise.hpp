#pragma once
// Noise on a logged input, carried to the outputs. An input logged with white noise of
// standard deviation σ (`inputs: { T_e: { column: …, noise: σ } }`) drives the simulation
// with a noise the real line never felt: the simulated outputs carry it through the model's
// dynamics (low-passed by the inertias, rung by the modes), and the residual with it,
// coloured. It is found by the input sensitivity applied to the noise: for R white sequences
// z_r (one value per sample of each noisy input, drawn with a fixed seed), the outputs'
// central difference
//     δy_r = (y(u + σ z_r) − y(u − σ z_r)) / 2
// at the noise's own amplitude (the input sensitivity S σ z_r for a model linear in the
// input; the slope over ±σ otherwise). A speed input's rate is the rate of its noisy samples.
// Averaged over the draws and the scored samples of each window, δy's lagged products are the
// propagated noise's auto- and cross-covariances, E[δy_a(t) δy_b(t + l)]: what the residual at
// the true parameters holds besides the outputs' own measurement noise.

#include <cstddef>
#include <string>
#include <vector>

#include "tvid/estimation/identification_problem.hpp"

namespace tvid {

/// The noise sequences drawn (each simulated twice).
constexpr int kInputNoiseDraws = 8;

/// Whether an input of `d` declares its noise.
bool declares_input_noise(const ProblemDefinition& d);

/// δy of each draw: [draw][window][output][scored sample], the windows in the order given.
/// Empty when no input declares noise; a draw whose simulation failed in some window is left
/// out (every window of a kept draw has its scored samples).
struct InputNoiseResponses {
    std::vector<std::vector<std::vector<std::vector<double>>>> delta;
    int failed_draws = 0;
    /// [input][output][τ], τ = 0 … kCrossCovarianceLags: E[n_q(t) δ_a(t + τ)], input q's noise
    /// n_q = σ_q z_q with what it carries to output a τ samples later, over the kept draws and
    /// the pairs of scored samples within a window (the residual analysis's expectation,
    /// analysis/residual_correlation.hpp); the inputs in InputChannels order, empty for one
    /// without noise.
    std::vector<std::vector<std::vector<double>>> input_cross;
};

/// The lags of InputNoiseResponses::input_cross (those of the residual analysis).
constexpr int kCrossCovarianceLags = 25;

/// The responses at the full parameter vector `params`, on `threads` threads (<= 0: all);
/// the same numbers on any thread count.
InputNoiseResponses input_noise_responses(const IdentificationProblem& problem, const std::vector<double>& params,
                                          const std::vector<const Window*>& windows, int draws = kInputNoiseDraws,
                                          int threads = 1);

/// The propagated noise's correlation counts as gone below this share of its lag-0 value.
constexpr double kPropagatedCorrelationFloor = 0.05;

/// The propagated noise's covariances between outputs at lags 0 … lags.
struct PropagatedInputNoise {
    bool available = false;
    int draws = 0;
    int lags = 0;
    /// [a][b][l] = mean over the draws and the sample pairs (t, t + l) within a window of
    /// δy_a(t) δy_b(t + l); in the outputs' units.
    std::vector<std::vector<std::vector<double>>> covariance;
    /// The first lag l from which every auto-covariance stays within kPropagatedCorrelationFloor
    /// of its lag-0 value, or within three standard errors of its estimate, up to lag 2l (at
    /// most `lags`): the reach of the noise's memory.
    int correlation_lags = 0;
    /// Output a's propagated noise: its standard deviation.
    double rms(std::size_t a) const;
};

/// The covariances of `responses` up to `lags` (fewer when a window is shorter than 2·lags).
/// `outputs`: how many outputs each window holds.
PropagatedInputNoise propagated_covariance(const InputNoiseResponses& responses, std::size_t outputs, int lags);

}  // namespace tvid

#pragma once
// The judgement of a finished fit (analysis/verdict.hpp): the figures it rests on — residual
// whiteness and correlations per output and split, the information criteria, the RK4 step's stability
// margin, bound-aware intervals — and the findings drawn from them. run_fit calls it last.

#include "tvid/fit/fit_run.hpp"

namespace tvid {

// The thresholds of the findings (docs/report-format.md, "verdict").
/// A residual with at least this share of systematic variance is an error; from
/// kSystematicShareWarning on (with a Ljung–Box p below kWhitenessP) a warning.
constexpr double kSystematicShareError = 0.5;
constexpr double kSystematicShareWarning = 0.1;
constexpr double kWhitenessP = 1e-3;
/// The residual analysis (analysis/residual_correlation.hpp): a correlation outside its 99 %
/// band at more than kCorrelationChanceShare of the lags tested plus kCorrelationLagMargin
/// lags is more than chance (a white residual leaves 1 % of its lags outside; 3 or more of
/// the 26 lags τ = 0 … 25 happen to 0.2 % of white residuals when the lags are independent,
/// and to at most about 1 % when a smooth input makes neighbouring lags cross together, as
/// the 99 % band says). An input's cross-correlation
/// is judged at τ ≥ 0, where the residual follows the input (missing_input_dynamic); the
/// autocorrelation at k ≥ 1 (residual_autocorrelation).
constexpr double kCorrelationChanceShare = 0.01;
constexpr int kCorrelationLagMargin = 2;
/// A pooled fit from this on is exact (noise-free data): its residual is not judged.
constexpr double kExactFitPercent = 99.99;
/// Validation RMSE over estimation RMSE (each over its sample-to-sample noise).
constexpr double kValidationWorseWarning = 1.1;
constexpr double kValidationWorseError = 2.0;
/// A parameter within this fraction of its box width of a bound (and within 1 % of its
/// value) is on the bound.
constexpr double kNearBound = 1e-3;
/// Failed candidate simulations above this share of all of them: a warning.
constexpr double kFailedShareWarning = 0.25;
/// Multistart: another start within this relative cost of the best, at parameters more
/// than kDistinctRelative (and 3 standard errors) away, is a second optimum.
constexpr double kNearEqualCost = 0.01;
constexpr double kDistinctRelative = 0.1;
/// A dry friction or road load whose measured speed in motion lies within 3 smoothing speeds
/// of zero (experiment/smoothing_speeds.hpp) at this share of the samples or more: a warning.
constexpr double kSmoothedShareWarning = 0.2;
/// RK4's stability margin from which a warning is given. Never an error: the simulation
/// finished (a margin a little above 1 at a window's start is passed through by an engine,
/// whose inertia changes with crank angle), but a slightly stiffer candidate blows up.
constexpr double kStepMarginWarning = 0.8;
/// A linear search box (range, or bounds) of more decades than this: a warning that
/// suggests `scale: log`.
constexpr double kWideBoxDecades = 2.0;
/// A window whose fit % is this many points below its split's pooled fit (or below 0), with
/// a systematic residual.
constexpr double kPoorWindowPoints = 30.0;

/// Weakly determined parameters linked by |correlation| from this on form a group whose
/// best-determined combination the verdict names (weak_apart, analysis/determined_combinations.hpp).
constexpr double kCorrelatedGroup = 0.9;
/// An optimizer's best from which one Gauss–Newton step would still lower the l2 cost by more
/// than this share (and by more than one σ² of the residuals) is not a minimum
/// (`not_at_minimum`): the "cost within 1 %" a global search is asked for.
constexpr double kNotAtMinimumShare = 0.01;

/// The swarm has not converged when, at its end, its global best still fell by more than
/// this relative amount over its last iterations (PsoConvergence::window), or the particles'
/// personal bests still span more than this share of the box in some parameter.
constexpr double kSwarmStillImproving = 1e-3;
constexpr double kSwarmStillSpread = 0.05;

/// A delay parameter within this many samples of half way between two samples, whose cost
/// one sample on comes within this fraction of its rise to the nearest whole sample, is
/// judged to buy the interpolation's smoothing (delay_smoothing).
constexpr double kHalfSampleBand = 0.15;
constexpr double kHalfSampleRecurrence = 0.5;

/// Whether `outside` of `tested` lags outside the 99 % band are more than chance.
bool correlation_beyond_chance(int outside, int tested);

/// Whether a residual passes the whiteness test: Ljung–Box p ≥ kWhitenessP. A white residual
/// has no band or order worth naming (the terminal and spectra.png then name none).
bool residual_is_white(const ResidualWhiteness& w);

/// The inputs whose cross-correlation with the residuals the residual analysis computes:
/// those read by time (a crank-angle channel has no value per time sample), as indices into
/// experiment.inputs, in the order of FitResult::correlation_*.cross_correlation.
std::vector<std::size_t> correlated_inputs(const Experiment& experiment);

/// Fills fit's whiteness, residual correlations, criteria, stability, interval kinds and verdict.
/// `threads`: for the simulations of a declared input noise (analysis/input_noise.hpp).
void judge_fit(const IdentificationProblem& problem, FitResult& fit, int threads = 1);

}  // namespace tvid

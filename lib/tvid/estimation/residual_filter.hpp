#pragma once
// How an output's residuals are scored within a window, beyond the raw difference: with
// their mean or linear trend removed (`detrend`), and high-pass filtered (`highpass`),
// for outputs such as speeds that drift slowly in ways no input explains. Each is a
// linear map of the window's residual sequence, so applying it to the residuals and to
// each column of their Jacobian keeps the two consistent.

#include <cstddef>

#include "tvid/experiment/experiment.hpp"

namespace tvid {

/// Applies `f` in place to the n residuals r[0], r[stride], … r[(n−1)·stride] of one output
/// in one window, sampled at times t[0 … n): first the detrend (the least-squares mean,
/// or line a + b·t), then the high-pass, a second-order Butterworth run forward and
/// backward (zero phase, fourth order in effect) at the window's mean sample interval,
/// from a zero state at each end.
void filter_residuals(const ScoringFilter& f, const double* t, double* r, std::size_t n, std::size_t stride);

}  // namespace tvid

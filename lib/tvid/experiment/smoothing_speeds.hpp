#pragma once
// The speed over which a dry friction's or a road load's sign is smoothed, from the data's
// own scale where the experiment does not give it. Within a few smoothing speeds of zero
// the smoothed sign is a viscous term (slope F/v_s): a fixed default in rad/s would smooth a
// linear axis that moves at 0.2 m/s over half its samples, and the fit would trade the
// Coulomb force against the viscous coefficient.

#include "tvid/experiment/experiment.hpp"

namespace tvid {

/// The default smoothing speed's share of the largest speed measured across the element.
inline constexpr double kSmoothingShareOfSpeed = 0.01;
/// The report's share of samples within this many smoothing speeds of zero (SmoothingChoice::share_within).
inline constexpr double kSmoothingShareSpeeds = 3.0;

/// Each dry (or direction-dependent) friction's and each road load's smoothing speed into
/// ex.smoothing; where the experiment does not give it, 1 % of the largest speed the
/// recordings show across the element (a node's own speed, or two measured nodes' relative
/// speed), carried through the gear ratios from the nodes that are measured, is written into
/// ex.network. Where no recorded speed reaches the element, the fixed default stays and the
/// basis says so.
void choose_smoothing_speeds(Experiment& ex);

}  // namespace tvid

#pragma once
// `initial_state: { kind: estimated, from: RECIPE }`: the parameters that hold each
// estimation window's start (NetworkSpec::start_coordinates). Each is a correction to the
// recipe's seed, so it starts at 0: every node's speed (but a speed source's, which the
// channel gives), and every node's angle but one per rigid rotation that neither the
// elements nor the outputs can see (on a line not tied to ground only the twists matter,
// and that node's angle stays the recipe's).

#include "tvid/experiment/experiment.hpp"

namespace tvid {

/// Appends the start parameters of every estimation window of `ex` to its network and
/// its parameters (ex.estimated_start.on). Throws InputError, naming initial_state, when
/// a name is taken.
void define_estimated_starts(Experiment& ex);

/// The search box half-widths of a start correction (a swarm's or multistart's box; LM
/// leaves them unbounded): an angle's ±kStartAngleRange [rad or m]; a speed's
/// ±kStartSpeedShare of the largest speed measured at its node or carried to it through the
/// gear ratios (a linear node's in m/s, a motor's behind a ball screw in rad/s); where no
/// measured speed reaches the node, that share of the largest of the nodes of its kind
/// (rotating or linear), at least ±kStartSpeedRange [rad/s or m/s].
inline constexpr double kStartAngleRange = 0.5;
inline constexpr double kStartSpeedShare = 0.1;
inline constexpr double kStartSpeedRange = 1.0;

}  // namespace tvid

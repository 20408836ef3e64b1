#pragma once
// The speeds the recordings show at the model's nodes: per sample where a channel reads a
// node's speed (a speed output, a speed source's input), and the largest each node turns
// at, carried through the gear ratios from the measured ones. The data's own speed scale,
// for defaults that have a unit (a friction's smoothing speed, a start speed's search box).

#include <vector>

#include "tvid/experiment/experiment.hpp"

namespace tvid {

/// Each node's measured speed per sample [rad/s, or m/s on a linear node], as the model
/// reads it (the channel's unit factor applied); empty where no channel reads it.
std::vector<std::vector<double>> measured_node_speeds(const Experiment& ex);

/// The largest finite |v| of v (0 when empty).
double largest_finite(const std::vector<double>& v);

/// The largest speed each node turns at: the measured nodes' largest, carried to every node
/// tied to them through the gear ratios at parameters `p` (model/steady_motion.hpp); 0 where
/// no measured speed reaches.
std::vector<double> node_speed_scales(const Experiment& ex, const std::vector<double>& p);

}  // namespace tvid

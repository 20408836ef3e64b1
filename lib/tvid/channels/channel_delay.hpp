#pragma once
// A channel recorded `delay` seconds late (a channel logged by another device, with its
// own latency), read on the model's time: at model time t it reads the recording at
// t + delay, interpolated linearly between samples and held at the recording's ends.
// The one rule for a delay, fixed or a parameter: problem_definition shifts every channel
// by it once, a workspace shifts the channels whose delay is a parameter at each candidate.

#include <cstddef>
#include <vector>

namespace tvid {

/// The recording `v` (at the strictly increasing `time`) at time t. `hint` is the caller's
/// cursor (the interval found last time): reading forward finds its interval in O(1).
double delayed_value(const std::vector<double>& v, const std::vector<double>& time, double t, std::size_t& hint);

/// The slope of that interpolation at t, d/dt of delayed_value: the slope of the interval
/// t lies in (the one starting at t on a sample), 0 where the ends are held. It is the
/// derivative of a residual against a delay parameter.
double delayed_slope(const std::vector<double>& v, const std::vector<double>& time, double t, std::size_t& hint);

/// out[i] = the recording at time[i] + delay, for every sample (out is resized to v's size).
void delay_channel(const std::vector<double>& v, const std::vector<double>& time, double delay, std::vector<double>& out);

/// The time derivative of a channel at its samples: central differences inside (second
/// order on a non-uniform grid), one-sided at the ends.
std::vector<double> sample_slopes(const std::vector<double>& v, const std::vector<double>& time);

}  // namespace tvid

#pragma once
// A channel recorded `delay` seconds late (a channel logged by another device, with its
// own latency), read on the model's time: at model time t it reads the recording at
// t + delay, held at the recording's ends. Between samples the recording is interpolated
// by cubic Hermite segments through the samples, with the slopes of sample_slopes at
// them: a whole-sample delay shifts the samples exactly, a straight line stays straight,
// and the reading is continuously differentiable in t, so a cost is smooth in a delay
// parameter across the sample times (a linear interpolation's slope would jump there).
// The one rule for a delay, fixed or a parameter: problem_definition shifts every channel
// by it once, a workspace shifts the channels whose delay is a parameter at each candidate.
// Several recordings end to end (recording_spans.hpp) are each read on their own: held at
// their own ends, their slopes one-sided there.

#include <cstddef>
#include <span>
#include <vector>

#include "tvid/channels/recording_spans.hpp"

namespace tvid {

/// A recording and its slopes at its samples (sample_slopes), on the strictly increasing `time`.
struct SampledSignal {
    std::span<const double> value;
    std::span<const double> slope;
    std::span<const double> time;
};

/// The part of `s` in rows `r`: one recording of several laid end to end.
SampledSignal signal_within(const SampledSignal& s, RowSpan r);

/// The recording at time t. `hint` is the caller's cursor (the interval found last time):
/// reading forward finds its interval in O(1).
double delayed_value(const SampledSignal& s, double t, std::size_t& hint);

/// d/dt of delayed_value at t (0 where the ends are held): the derivative of a residual
/// against a delay parameter.
double delayed_slope(const SampledSignal& s, double t, std::size_t& hint);

/// out[i] = the recording at time[i] + delay, for every sample (out is resized to v's size).
void delay_channel(const SampledSignal& s, double delay, std::vector<double>& out);
void delay_channel(const std::vector<double>& v, const std::vector<double>& time, double delay, std::vector<double>& out);
/// The same for several recordings end to end: each sample reads its own recording.
void delay_channel(const SampledSignal& s, const std::vector<RowSpan>& recordings, double delay,
                   std::vector<double>& out);
void delay_channel(const std::vector<double>& v, const std::vector<double>& time,
                   const std::vector<RowSpan>& recordings, double delay, std::vector<double>& out);

/// The time derivative of a channel at its samples: central differences inside (second
/// order on a non-uniform grid), one-sided at the ends.
std::vector<double> sample_slopes(const std::vector<double>& v, const std::vector<double>& time);
/// The same for several recordings end to end: one-sided at each recording's ends.
std::vector<double> sample_slopes(const std::vector<double>& v, const std::vector<double>& time,
                                  const std::vector<RowSpan>& recordings);

}  // namespace tvid

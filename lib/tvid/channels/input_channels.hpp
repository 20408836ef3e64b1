#pragma once
// The measured input channels of a recording, read-only and shared by all threads.
// Between samples an input is interpolated linearly (the paper's RK4 at the sampling
// interval then sees the mean of two samples at the half step).

#include <cstddef>
#include <vector>

namespace tvid {

class InputChannels {
public:
    InputChannels() = default;
    /// `values[k]` holds input k at every time stamp of `time` (strictly increasing).
    InputChannels(std::vector<double> time, std::vector<std::vector<double>> values);

    std::size_t count() const { return values_.size(); }
    std::size_t samples() const { return time_.size(); }
    const std::vector<double>& time() const { return time_; }
    double value(std::size_t input, std::size_t sample) const { return values_[input][sample]; }
    /// Input `input` half way between samples `sample` and sample + 1 (the linear
    /// interpolation there, computed once): RK4's middle stages at the sampling step.
    double midpoint(std::size_t input, std::size_t sample) const { return midpoints_[input][sample]; }
    /// Every input at sample `sample` into u[0 … count).
    void read_sample(std::size_t sample, double* u) const {
        for (std::size_t k = 0; k < values_.size(); ++k) u[k] = values_[k][sample];
    }

    /// Inputs at time t into u[0 … count). `hint` is the caller's cursor (the interval
    /// index found last time), so a simulation marching forward finds its interval in O(1).
    /// Outside the recording the end values are held.
    void at(double t, std::size_t& hint, double* u) const;

    /// Replaces input k's values (as many as there are samples) and its midpoints, in
    /// place: a workspace's copy shifted by a candidate's delay (channel_delay.hpp).
    void set_channel(std::size_t input, const std::vector<double>& values);

private:
    std::vector<double> time_;
    std::vector<std::vector<double>> values_;
    std::vector<std::vector<double>> midpoints_;
};

}  // namespace tvid

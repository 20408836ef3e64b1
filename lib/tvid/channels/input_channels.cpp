#include "tvid/channels/input_channels.hpp"

#include <algorithm>

namespace tvid {

InputChannels::InputChannels(std::vector<double> time, std::vector<std::vector<double>> values)
    : time_(std::move(time)), values_(std::move(values)) {
    midpoints_.resize(values_.size());
    for (std::size_t k = 0; k < values_.size(); ++k) set_channel(k, values_[k]);
}

void InputChannels::set_channel(std::size_t input, const std::vector<double>& values) {
    std::vector<double>& v = values_[input];
    if (&v != &values) v.assign(values.begin(), values.end());
    std::vector<double>& mid = midpoints_[input];
    mid.resize(v.empty() ? 0 : v.size() - 1);
    for (std::size_t i = 0; i + 1 < v.size(); ++i) mid[i] = v[i] + 0.5 * (v[i + 1] - v[i]);
}

void InputChannels::at(double t, std::size_t& hint, double* u) const {
    const std::size_t n = time_.size();
    if (n == 0) return;
    if (n == 1 || t <= time_.front()) {
        for (std::size_t k = 0; k < values_.size(); ++k) u[k] = values_[k].front();
        return;
    }
    if (t >= time_.back()) {
        for (std::size_t k = 0; k < values_.size(); ++k) u[k] = values_[k].back();
        return;
    }
    // Find i with time_[i] <= t < time_[i+1], starting from the hint.
    std::size_t i = std::min(hint, n - 2);
    if (time_[i] > t || time_[i + 1] <= t) {
        if (time_[i + 1] <= t && i + 2 < n && time_[i + 2] > t) {
            ++i;  // the common case: marched into the next interval
        } else {
            const auto it = std::upper_bound(time_.begin(), time_.end(), t);
            i = static_cast<std::size_t>(it - time_.begin()) - 1;
        }
    }
    hint = i;
    const double s = (t - time_[i]) / (time_[i + 1] - time_[i]);
    for (std::size_t k = 0; k < values_.size(); ++k) {
        const double a = values_[k][i];
        u[k] = a + s * (values_[k][i + 1] - a);
    }
}

}  // namespace tvid

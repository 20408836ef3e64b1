#include "tvid/channels/crank_angle_channels.hpp"

#include <algorithm>

namespace tvid {

CrankAngleChannels::CrankAngleChannels(std::vector<double> angle, std::vector<std::vector<double>> values)
    : angle_(std::move(angle)), values_(std::move(values)) {
    slopes_.resize(values_.size());
    for (std::size_t k = 0; k < values_.size(); ++k) {
        const std::vector<double>& v = values_[k];
        for (std::size_t i = 0; i + 1 < v.size() && i + 1 < angle_.size(); ++i)
            slopes_[k].push_back((v[i + 1] - v[i]) / (angle_[i + 1] - angle_[i]));
    }
}

std::size_t CrankAngleChannels::interval(double x, std::size_t& cursor) const {
    const std::size_t n = angle_.size();
    if (n < 2) return 0;
    std::size_t i = std::min(cursor, n - 2);
    if (angle_[i] <= x && x < angle_[i + 1]) return i;
    // A throw moves a fraction of a grid step per integrator stage: look next door first.
    if (i + 2 < n && angle_[i + 1] <= x && x < angle_[i + 2]) return cursor = i + 1;
    if (i > 0 && angle_[i - 1] <= x && x < angle_[i]) return cursor = i - 1;
    const auto it = std::upper_bound(angle_.begin(), angle_.end(), x);
    const auto found = static_cast<std::size_t>(std::max<std::ptrdiff_t>(it - angle_.begin() - 1, 0));
    return cursor = std::min(found, n - 2);
}

}  // namespace tvid

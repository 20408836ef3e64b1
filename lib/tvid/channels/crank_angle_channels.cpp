#include "tvid/channels/crank_angle_channels.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

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

CrankAngleChannels CrankAngleChannels::end_to_end(const std::vector<double>& angle,
                                                  const std::vector<std::vector<double>>& values,
                                                  const std::vector<RowSpan>& recordings) {
    if (recordings.size() <= 1) return CrankAngleChannels(angle, values);
    std::vector<double> grid;
    std::vector<std::vector<double>> held(values.size());
    for (std::size_t r = 0; r < recordings.size(); ++r) {
        const RowSpan span = recordings[r];
        grid.insert(grid.end(), angle.begin() + static_cast<std::ptrdiff_t>(span.begin),
                    angle.begin() + static_cast<std::ptrdiff_t>(span.end));
        for (std::size_t k = 0; k < values.size(); ++k)
            held[k].insert(held[k].end(), values[k].begin() + static_cast<std::ptrdiff_t>(span.begin),
                           values[k].begin() + static_cast<std::ptrdiff_t>(span.end));
        if (r + 1 == recordings.size()) break;
        // The gap to the next recording: this one's last value up to its middle, the next
        // one's first value from just after it.
        const std::size_t last = span.end - 1, next = recordings[r + 1].begin;
        const double middle = 0.5 * (angle[last] + angle[next]);
        grid.push_back(middle);
        grid.push_back(std::nextafter(middle, std::numeric_limits<double>::infinity()));
        for (std::size_t k = 0; k < values.size(); ++k) {
            held[k].push_back(values[k][last]);
            held[k].push_back(values[k][next]);
        }
    }
    return CrankAngleChannels(std::move(grid), std::move(held));
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

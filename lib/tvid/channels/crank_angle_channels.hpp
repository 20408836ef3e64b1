#pragma once
// Channels recorded against crank angle — the cylinder pressures of the methodology paper — looked up
// by an angle of the model, not by time: a throw's pressure is the measured pressure
// at that throw's own angle. The angle grid is the recording's cumulative crank angle
// [rad], strictly increasing; between grid points a channel is linear in the angle and
// beyond the ends its end value is held. Read-only and shared by all threads; each
// caller keeps its own cursor.

#include <array>
#include <cstddef>
#include <vector>

#include "tvid/channels/recording_spans.hpp"
#include "tvid/channels/scalar_value.hpp"
#include "tvid/simd/pack.hpp"

namespace tvid {

class CrankAngleChannels {
public:
    CrankAngleChannels() = default;
    CrankAngleChannels(std::vector<double> angle, std::vector<std::vector<double>> values);
    /// Several recordings end to end (recording_spans.hpp), `angle` rising across them with
    /// a gap between two recordings wider than a throw ever twists past its recording's end
    /// (a cycle: experiment/recording_join.hpp). Each recording's channel is held at its ends
    /// as that recording alone holds it: the grid gains two points in the middle of each
    /// gap, holding each side flat up to there, so that no throw reads the next recording.
    static CrankAngleChannels end_to_end(const std::vector<double>& angle, const std::vector<std::vector<double>>& values,
                                         const std::vector<RowSpan>& recordings);

    std::size_t count() const { return values_.size(); }
    bool empty() const { return values_.empty(); }
    const std::vector<double>& angle() const { return angle_; }

    /// Channel k at angle a (any scalar type: the slope carries derivatives), using and
    /// updating the caller's cursor so that a simulation moving forward finds its
    /// interval in O(1).
    template <class T>
    T at(std::size_t k, const T& a, std::size_t& cursor) const {
        const double x = scalar_value(a);
        const std::size_t i = interval(x, cursor);
        const std::vector<double>& v = values_[k];
        if (x <= angle_.front()) return T(v.front());
        if (x >= angle_.back()) return T(v.back());
        return v[i] + slopes_[k][i] * (a - angle_[i]);
    }

    /// Channel k at the angles of the lanes of a pack, each lane with its own cursor.
    template <int W>
    Pack<W> at(std::size_t k, const Pack<W>& a, std::array<std::size_t, static_cast<std::size_t>(W)>& cursors) const {
        Pack<W> r;
        for (int lane = 0; lane < W; ++lane) r.set(lane, at(k, a[lane], cursors[static_cast<std::size_t>(lane)]));
        return r;
    }

private:
    /// i with angle_[i] <= x < angle_[i+1] (clamped to the grid).
    std::size_t interval(double x, std::size_t& cursor) const;

    std::vector<double> angle_;
    std::vector<std::vector<double>> values_;
    std::vector<std::vector<double>> slopes_;  ///< (v[i+1] − v[i]) / (angle[i+1] − angle[i]), computed once
};

/// A caller's cursor into the angle grid for scalar type T: one per lane for a pack.
template <class T>
struct AngleCursorOf {
    using type = std::size_t;
};
template <int W>
struct AngleCursorOf<Pack<W>> {
    using type = std::array<std::size_t, static_cast<std::size_t>(W)>;
};
template <class T>
using AngleCursor = typename AngleCursorOf<T>::type;

}  // namespace tvid

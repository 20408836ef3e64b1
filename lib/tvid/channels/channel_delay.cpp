#include "tvid/channels/channel_delay.hpp"

#include <algorithm>

namespace tvid {

namespace {

// The interval [time[j], time[j + 1]) holding t, for t strictly inside the recording.
std::size_t interval(const std::vector<double>& time, double t, std::size_t& hint) {
    const std::size_t n = time.size();
    std::size_t j = std::min(hint, n - 2);
    if (time[j] > t || time[j + 1] <= t) {
        if (time[j + 1] <= t && j + 2 < n && time[j + 2] > t) {
            ++j;  // the common case: read on into the next interval
        } else {
            j = static_cast<std::size_t>(std::upper_bound(time.begin(), time.end(), t) - time.begin()) - 1;
        }
    }
    hint = j;
    return j;
}

bool held(const std::vector<double>& time, double t) {
    return time.size() < 2 || t <= time.front() || t >= time.back();
}

}  // namespace

double delayed_value(const std::vector<double>& v, const std::vector<double>& time, double t, std::size_t& hint) {
    if (v.empty()) return 0.0;
    if (held(time, t)) return t >= time.back() ? v.back() : v.front();
    const std::size_t j = interval(time, t, hint);
    const double a = (t - time[j]) / (time[j + 1] - time[j]);
    return v[j] + a * (v[j + 1] - v[j]);
}

double delayed_slope(const std::vector<double>& v, const std::vector<double>& time, double t, std::size_t& hint) {
    if (v.empty() || held(time, t)) return 0.0;
    const std::size_t j = interval(time, t, hint);
    return (v[j + 1] - v[j]) / (time[j + 1] - time[j]);
}

void delay_channel(const std::vector<double>& v, const std::vector<double>& time, double delay, std::vector<double>& out) {
    out.resize(v.size());
    if (delay == 0.0) {
        std::copy(v.begin(), v.end(), out.begin());
        return;
    }
    std::size_t hint = 0;
    for (std::size_t i = 0; i < v.size(); ++i) out[i] = delayed_value(v, time, time[i] + delay, hint);
}

std::vector<double> sample_slopes(const std::vector<double>& v, const std::vector<double>& time) {
    const std::size_t n = v.size();
    std::vector<double> out(n, 0.0);
    if (n < 2) return out;
    out.front() = (v[1] - v[0]) / (time[1] - time[0]);
    out.back() = (v[n - 1] - v[n - 2]) / (time[n - 1] - time[n - 2]);
    for (std::size_t i = 1; i + 1 < n; ++i) {
        const double h0 = time[i] - time[i - 1], h1 = time[i + 1] - time[i];
        out[i] = (h0 * h0 * (v[i + 1] - v[i]) + h1 * h1 * (v[i] - v[i - 1])) / (h0 * h1 * (h0 + h1));
    }
    return out;
}

}  // namespace tvid

#include "tvid/channels/channel_delay.hpp"

#include <algorithm>

namespace tvid {

namespace {

// The interval [time[j], time[j + 1]) holding t, for t strictly inside the recording.
std::size_t interval(std::span<const double> time, double t, std::size_t& hint) {
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

bool held(std::span<const double> time, double t) {
    return time.size() < 2 || !(t > time.front() && t < time.back());
}

// out[i] = the recording at time[i] + delay, for the samples of `s`.
void delay_into(const SampledSignal& s, double delay, double* out) {
    if (delay == 0.0) {
        std::copy(s.value.begin(), s.value.end(), out);
        return;
    }
    std::size_t hint = 0;
    for (std::size_t i = 0; i < s.value.size(); ++i) out[i] = delayed_value(s, s.time[i] + delay, hint);
}

// The slopes of sample_slopes for the samples of one recording.
void slopes_into(std::span<const double> v, std::span<const double> time, double* out) {
    const std::size_t n = v.size();
    std::fill(out, out + n, 0.0);
    if (n < 2) return;
    out[0] = (v[1] - v[0]) / (time[1] - time[0]);
    out[n - 1] = (v[n - 1] - v[n - 2]) / (time[n - 1] - time[n - 2]);
    for (std::size_t i = 1; i + 1 < n; ++i) {
        const double h0 = time[i] - time[i - 1], h1 = time[i + 1] - time[i];
        out[i] = (h0 * h0 * (v[i + 1] - v[i]) + h1 * h1 * (v[i] - v[i - 1])) / (h0 * h1 * (h0 + h1));
    }
}

std::span<const double> rows_of(std::span<const double> v, RowSpan r) { return v.subspan(r.begin, r.size()); }

}  // namespace

SampledSignal signal_within(const SampledSignal& s, RowSpan r) {
    return {rows_of(s.value, r), rows_of(s.slope, r), rows_of(s.time, r)};
}

double delayed_value(const SampledSignal& s, double t, std::size_t& hint) {
    const std::span<const double> v = s.value;
    if (v.empty()) return 0.0;
    if (held(s.time, t)) return t >= s.time.back() ? v.back() : v.front();
    const std::size_t j = interval(s.time, t, hint);
    const double h = s.time[j + 1] - s.time[j], a = (t - s.time[j]) / h;
    if (a == 0.0) return v[j];  // on a sample: the sample itself
    // Cubic Hermite on [t_j, t_j+1]: the values and the slopes at both ends.
    const double a2 = a * a, a3 = a2 * a;
    const double h00 = 2 * a3 - 3 * a2 + 1, h10 = a3 - 2 * a2 + a, h01 = -2 * a3 + 3 * a2, h11 = a3 - a2;
    return h00 * v[j] + h10 * h * s.slope[j] + h01 * v[j + 1] + h11 * h * s.slope[j + 1];
}

double delayed_slope(const SampledSignal& s, double t, std::size_t& hint) {
    if (s.value.empty() || held(s.time, t)) return 0.0;
    const std::size_t j = interval(s.time, t, hint);
    const double h = s.time[j + 1] - s.time[j], a = (t - s.time[j]) / h;
    const double a2 = a * a;
    const double d00 = 6 * a2 - 6 * a, d10 = 3 * a2 - 4 * a + 1, d01 = -6 * a2 + 6 * a, d11 = 3 * a2 - 2 * a;
    return (d00 * s.value[j] + d01 * s.value[j + 1]) / h + d10 * s.slope[j] + d11 * s.slope[j + 1];
}

void delay_channel(const SampledSignal& s, double delay, std::vector<double>& out) {
    out.resize(s.value.size());
    delay_into(s, delay, out.data());
}

void delay_channel(const std::vector<double>& v, const std::vector<double>& time, double delay, std::vector<double>& out) {
    if (delay == 0.0) {
        out = v;
        return;
    }
    const std::vector<double> slope = sample_slopes(v, time);
    delay_channel(SampledSignal{v, slope, time}, delay, out);
}

void delay_channel(const SampledSignal& s, const std::vector<RowSpan>& recordings, double delay,
                   std::vector<double>& out) {
    out.resize(s.value.size());
    for (const RowSpan& r : recordings) delay_into(signal_within(s, r), delay, out.data() + r.begin);
}

void delay_channel(const std::vector<double>& v, const std::vector<double>& time,
                   const std::vector<RowSpan>& recordings, double delay, std::vector<double>& out) {
    if (delay == 0.0) {
        out = v;
        return;
    }
    const std::vector<double> slope = sample_slopes(v, time, recordings);
    delay_channel(SampledSignal{v, slope, time}, recordings, delay, out);
}

std::vector<double> sample_slopes(const std::vector<double>& v, const std::vector<double>& time) {
    std::vector<double> out(v.size(), 0.0);
    slopes_into(v, time, out.data());
    return out;
}

std::vector<double> sample_slopes(const std::vector<double>& v, const std::vector<double>& time,
                                  const std::vector<RowSpan>& recordings) {
    std::vector<double> out(v.size(), 0.0);
    for (const RowSpan& r : recordings) slopes_into(rows_of(v, r), rows_of(time, r), out.data() + r.begin);
    return out;
}

}  // namespace tvid

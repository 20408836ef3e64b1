#include "tvid/experiment/window_reader.hpp"

#include "tvid/util/text.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace tvid {

namespace {

class WindowResolver {
public:
    WindowResolver(const YamlSource& src, const RecordingAxes& axes, double warmup, int warmup_cycles)
        : src_(src), axes_(axes), time_(axes.time), warmup_(warmup), warmup_cycles_(warmup_cycles),
          recording_(axes.name.empty() ? "the recording" : "recording " + axes.name),
          data_(axes.name.empty() ? "the data" : "the data of recording " + axes.name) {
        tolerance_ = 1e-3 * smallest_step(time_);  // time stamps written with rounding still match
        if (!axes.crank_deg.empty()) {
            angle_tolerance_ = 1e-3 * smallest_step(axes.crank_deg);
            const double c = axes.cycle_deg;
            first_cycle_start_ = std::ceil(axes.crank_deg.front() / c - 1e-9) * c;
            // Clamped: a crank angle of 1e300 deg must not overflow the count.
            cycle_count_ = static_cast<long long>(
                std::min(std::floor((axes.crank_deg.back() - first_cycle_start_) / c + 1e-9), 1e15));
        }
    }

    /// The window `m` on this recording's own rows; `whole`: it names only its recording,
    /// and covers all of it.
    Window one(const YamlMap& m, bool whole) const {
        Window w;
        if (whole) {
            w.first = 0;
            w.last = time_.size() - 1;
            w.label = "whole recording";
            w.where = src_.where(m.node(), m.path());
        } else {
            resolve_span(m, w);
        }
        w.start = w.first;
        if (warmup_cycles_ > 0) {
            const double start_deg = axes_.crank_deg[w.first] - warmup_cycles_ * axes_.cycle_deg;
            if (start_deg < axes_.crank_deg.front() - angle_tolerance_)
                src_.fail(m.node(), m.path(), "the warm-up of " + std::to_string(warmup_cycles_) +
                                                  " cycle(s) before this window starts before " + recording_ + " (" +
                                                  cycles_text() + ")");
            w.start = sample_at_angle(start_deg);
        }
        if (warmup_ > 0) {
            const double t0 = time_[w.first] - warmup_;
            if (t0 < time_.front() - tolerance_)
                src_.fail(m.node(), m.path(), "the warm-up of " + number_text(warmup_) + " s before this window starts at t = " +
                                                  number_text(t0) + " s, before " + recording_ + " (t = " +
                                                  number_text(time_.front()) + " s)");
            w.start = static_cast<std::size_t>(
                std::lower_bound(time_.begin(), time_.end(), t0 - tolerance_) - time_.begin());
        }
        return w;
    }

private:
    static double smallest_step(const std::vector<double>& v) {
        double smallest = v.size() > 1 ? v[1] - v[0] : 1.0;
        for (std::size_t i = 1; i < v.size(); ++i) smallest = std::min(smallest, v[i] - v[i - 1]);
        return smallest;
    }

    // The sample at crank angle `deg` (within the angle tolerance), or the first after it.
    std::size_t sample_at_angle(double deg) const {
        const auto& a = axes_.crank_deg;
        return static_cast<std::size_t>(std::lower_bound(a.begin(), a.end(), deg - angle_tolerance_) - a.begin());
    }

    std::string cycles_text() const {
        return cycle_count_ > 0 ? recording_ + " holds complete cycles 0 … " + std::to_string(cycle_count_ - 1)
                                : recording_ + " holds no complete cycle";
    }

    // Cycles a … b (inclusive): from the start of cycle a to the start of cycle b + 1.
    void resolve_cycles(const YamlMap& m, const std::string& key, long long a, long long b, Window& w) const {
        const YAML::Node node = m.get(key);
        const std::string path = m.key_path(key);
        if (axes_.crank_deg.empty())
            src_.fail(node, path, "cycle windows need the crank-angle channel: give data.angle");
        if (a < 0 || b >= cycle_count_)
            src_.fail(node, path, "cycle " + std::to_string(a < 0 ? a : b) + " is outside the data: " + cycles_text());
        if (b < a) src_.fail(node, path, "the first cycle must not come after the last");
        const double c = axes_.cycle_deg;
        w.first = sample_at_angle(first_cycle_start_ + static_cast<double>(a) * c);
        w.last = sample_at_angle(first_cycle_start_ + static_cast<double>(b + 1) * c);
        if (w.last >= time_.size()) w.last = time_.size() - 1;
        w.label = a == b ? "cycle " + std::to_string(a) : "cycles " + std::to_string(a) + " to " + std::to_string(b);
        w.where = src_.where(node, path);
        if (w.last <= w.first) src_.fail(node, path, "the cycle holds fewer than two samples");
    }

    // time: [a, b], samples: [a, b], cycle: k or cycles: [a, b], on this recording.
    void resolve_span(const YamlMap& m, Window& w) const {
        const int given = int(m.has("time")) + int(m.has("samples")) + int(m.has("cycle")) + int(m.has("cycles"));
        if (given > 1)
            m.fail(m.has("cycles") ? "cycles" : m.has("cycle") ? "cycle" : "samples",
                   "give only one of time: [a, b], samples: [a, b], cycle: k or cycles: [a, b], not both");
        if (given == 0)
            m.fail_missing("time", "(give one of time: [a, b], samples: [a, b], cycle: k or cycles: [a, b])");
        const std::string extent = recording_ + " spans t = " + number_text(time_.front()) + " … " +
                                      number_text(time_.back()) + " s (" + std::to_string(time_.size()) + " samples)";
        if (m.has("time")) {
            const std::string key = m.key_path("time");
            const YAML::Node node = m.get("time");
            const auto [a, b] = read_interval(src_, node, key, true);
            if (a < time_.front() - tolerance_ || b > time_.back() + tolerance_)
                src_.fail(node, key, "window [" + number_text(a) + ", " + number_text(b) + "] s is outside the data: " +
                                         extent);
            w.first = static_cast<std::size_t>(
                std::lower_bound(time_.begin(), time_.end(), a - tolerance_) - time_.begin());
            w.last = static_cast<std::size_t>(
                std::upper_bound(time_.begin(), time_.end(), b + tolerance_) - time_.begin() - 1);
            w.label = "time " + number_text(a) + " to " + number_text(b);
            w.where = src_.where(node, key);
            if (w.last <= w.first) src_.fail(node, key, "window holds fewer than two samples: " + extent);
        } else if (m.has("cycle")) {
            const long long k = m.integer("cycle");
            resolve_cycles(m, "cycle", k, k, w);
        } else if (m.has("cycles")) {
            const YAML::Node node = m.get("cycles");
            const std::string key = m.key_path("cycles");
            if (!node.IsSequence() || node.size() != 2) src_.fail(node, key, "expected two cycle numbers [first, last]");
            resolve_cycles(m, "cycles", read_integer(src_, node[0], key), read_integer(src_, node[1], key), w);
        } else {
            const std::string key = m.key_path("samples");
            const YAML::Node node = m.get("samples");
            if (!node.IsSequence() || node.size() != 2) src_.fail(node, key, "expected two sample indices [first, last]");
            const long long a = read_integer(src_, node[0], key), b = read_integer(src_, node[1], key);
            if (a < 0 || b >= static_cast<long long>(time_.size()))
                src_.fail(node, key, "samples [" + std::to_string(a) + ", " + std::to_string(b) +
                                         "] are outside " + data_ + ": rows 0 … " + std::to_string(time_.size() - 1));
            if (b <= a) src_.fail(node, key, "the first sample must come before the last");
            w.first = static_cast<std::size_t>(a);
            w.last = static_cast<std::size_t>(b);
            w.label = "samples " + std::to_string(a) + " to " + std::to_string(b);
            w.where = src_.where(node, key);
        }
    }

    const YamlSource& src_;
    const RecordingAxes& axes_;
    const std::vector<double>& time_;
    double warmup_;
    int warmup_cycles_;
    double tolerance_ = 0.0;
    double angle_tolerance_ = 0.0;
    std::string recording_;           ///< "the recording", or "recording NAME"
    std::string data_;                ///< "the data", or "the data of recording NAME"
    double first_cycle_start_ = 0.0;  ///< [deg] the first multiple of the cycle at or after the first sample
    long long cycle_count_ = 0;       ///< complete cycles in the recording
};

// Which recording window `m` lies in: the one it names, or the only one.
std::size_t recording_of(const YamlMap& m, const std::vector<RecordingAxes>& recordings) {
    std::string names;
    for (const RecordingAxes& r : recordings) names += (names.empty() ? "" : ", ") + r.name;
    if (m.has("recording")) {
        const std::string name = m.text("recording");
        for (std::size_t k = 0; k < recordings.size(); ++k)
            if (recordings[k].name == name) return k;
        m.fail("recording", "no recording named '" + name + "' (data.recordings: " + names + ")");
    }
    if (recordings.size() > 1)
        m.fail_missing("recording", "(the experiment reads several recordings: name this window's, one of " + names + ")");
    return 0;
}

// windows.KEY: a list of windows, each resolved on its recording and placed in its rows.
std::vector<Window> read_window_list(const YamlMap& windows, const std::string& key, bool required,
                                     const std::vector<RecordingAxes>& recordings,
                                     const std::vector<WindowResolver>& resolvers) {
    std::vector<Window> out;
    if (!windows.has(key)) {
        if (required) windows.fail_missing(key, "(a list of windows, e.g. [ { time: [1.5, 3.0] } ])");
        return out;
    }
    const YamlSource& src = windows.source();
    const YAML::Node list = windows.get(key);
    const std::string path = windows.key_path(key);
    if (!list.IsSequence()) src.fail(list, path, "expected a list of windows, e.g. [ { time: [1.5, 3.0] } ]");
    if (required && list.size() == 0) src.fail(list, path, "at least one window is needed");
    const bool listed = !recordings.front().name.empty();  // data.recordings
    for (std::size_t i = 0; i < list.size(); ++i) {
        const YamlMap m(src, list[i], path + "[" + std::to_string(i) + "]");
        if (listed) {
            m.allow_only({"recording", "time", "samples", "cycle", "cycles"});
        } else {
            if (m.has("recording"))
                m.fail("recording", "names an entry of data.recordings, and this experiment reads one data.file: "
                                    "leave it out");
            m.allow_only({"time", "samples", "cycle", "cycles"});
        }
        const std::size_t k = recording_of(m, recordings);
        const bool whole = m.has("recording") && !m.has("time") && !m.has("samples") && !m.has("cycle") &&
                           !m.has("cycles");
        Window w = resolvers[k].one(m, whole);
        const std::size_t shift = recordings[k].first_row;
        w.start += shift;
        w.first += shift;
        w.last += shift;
        w.recording = k;
        if (listed) w.label = recordings[k].name + ": " + w.label;
        out.push_back(std::move(w));
    }
    return out;
}

}  // namespace

WindowSet read_windows(const YamlMap& windows, const std::vector<RecordingAxes>& recordings) {
    windows.allow_only({"estimation", "validation", "warmup"});
    WindowSet set;
    if (windows.has("warmup") && windows.get("warmup").IsMap()) {
        const YamlMap warmup = windows.map("warmup");
        warmup.allow_only({"cycles"});
        const long long n = warmup.integer("cycles");
        if (n < 0 || n > 1000) warmup.fail("cycles", "the warm-up must be 0 to 1000 cycles");
        if (n > 0 && recordings.front().crank_deg.empty())
            warmup.fail("cycles", "a warm-up in cycles needs the crank-angle channel: give data.angle");
        set.warmup_cycles = static_cast<int>(n);
    } else if (windows.has("warmup")) {
        set.warmup = windows.number("warmup");
        if (set.warmup < 0) windows.fail("warmup", "the warm-up cannot be negative");
    }
    std::vector<WindowResolver> resolvers;
    resolvers.reserve(recordings.size());
    for (const RecordingAxes& r : recordings) resolvers.emplace_back(windows.source(), r, set.warmup, set.warmup_cycles);
    set.estimation = read_window_list(windows, "estimation", true, recordings, resolvers);
    set.validation = read_window_list(windows, "validation", false, recordings, resolvers);
    return set;
}

}  // namespace tvid

#include "tvid/experiment/window_reader.hpp"

#include "tvid/util/text.hpp"

#include <algorithm>
#include <cstdio>

namespace tvid {

namespace {

class WindowResolver {
public:
    WindowResolver(const YamlSource& src, const std::vector<double>& time, double warmup)
        : src_(src), time_(time), warmup_(warmup) {
        double smallest = time.size() > 1 ? time[1] - time[0] : 1.0;
        for (std::size_t i = 1; i < time.size(); ++i) smallest = std::min(smallest, time[i] - time[i - 1]);
        tolerance_ = 1e-3 * smallest;  // time stamps written with rounding still match
    }

    std::vector<Window> list(const YamlMap& windows, const std::string& key, bool required) const {
        std::vector<Window> out;
        if (!windows.has(key)) {
            if (required) windows.fail_missing(key, "(a list of windows, e.g. [ { time: [1.5, 3.0] } ])");
            return out;
        }
        const YAML::Node list = windows.get(key);
        const std::string path = windows.key_path(key);
        if (!list.IsSequence()) src_.fail(list, path, "expected a list of windows, e.g. [ { time: [1.5, 3.0] } ]");
        if (required && list.size() == 0) src_.fail(list, path, "at least one window is needed");
        for (std::size_t i = 0; i < list.size(); ++i)
            out.push_back(one(YamlMap(src_, list[i], path + "[" + std::to_string(i) + "]")));
        return out;
    }

private:
    Window one(const YamlMap& m) const {
        m.allow_only({"time", "samples"});
        if (m.has("time") && m.has("samples"))
            m.fail("samples", "give either time: [a, b] or samples: [a, b], not both");
        if (!m.has("time") && !m.has("samples"))
            m.fail_missing("time", "(give exactly one of time: [a, b] or samples: [a, b])");
        Window w;
        const std::string recording = "the recording spans t = " + number_text(time_.front()) + " … " +
                                      number_text(time_.back()) + " s (" + std::to_string(time_.size()) + " samples)";
        if (m.has("time")) {
            const std::string key = m.key_path("time");
            const YAML::Node node = m.get("time");
            const auto [a, b] = read_interval(src_, node, key, true);
            if (a < time_.front() - tolerance_ || b > time_.back() + tolerance_)
                src_.fail(node, key, "window [" + number_text(a) + ", " + number_text(b) + "] s is outside the data: " +
                                         recording);
            w.first = static_cast<std::size_t>(
                std::lower_bound(time_.begin(), time_.end(), a - tolerance_) - time_.begin());
            w.last = static_cast<std::size_t>(
                std::upper_bound(time_.begin(), time_.end(), b + tolerance_) - time_.begin() - 1);
            w.label = "time " + number_text(a) + " to " + number_text(b);
            w.where = src_.where(node, key);
            if (w.last <= w.first) src_.fail(node, key, "window holds fewer than two samples: " + recording);
        } else {
            const std::string key = m.key_path("samples");
            const YAML::Node node = m.get("samples");
            if (!node.IsSequence() || node.size() != 2) src_.fail(node, key, "expected two sample indices [first, last]");
            const long long a = read_integer(src_, node[0], key), b = read_integer(src_, node[1], key);
            if (a < 0 || b >= static_cast<long long>(time_.size()))
                src_.fail(node, key, "samples [" + std::to_string(a) + ", " + std::to_string(b) +
                                         "] are outside the data: rows 0 … " + std::to_string(time_.size() - 1));
            if (b <= a) src_.fail(node, key, "the first sample must come before the last");
            w.first = static_cast<std::size_t>(a);
            w.last = static_cast<std::size_t>(b);
            w.label = "samples " + std::to_string(a) + " to " + std::to_string(b);
            w.where = src_.where(node, key);
        }
        w.start = w.first;
        if (warmup_ > 0) {
            const double t0 = time_[w.first] - warmup_;
            if (t0 < time_.front() - tolerance_)
                src_.fail(m.node(), m.path(), "the warm-up of " + number_text(warmup_) + " s before this window starts at t = " +
                                                  number_text(t0) + " s, before the recording (t = " +
                                                  number_text(time_.front()) + " s)");
            w.start = static_cast<std::size_t>(
                std::lower_bound(time_.begin(), time_.end(), t0 - tolerance_) - time_.begin());
        }
        return w;
    }

    const YamlSource& src_;
    const std::vector<double>& time_;
    double warmup_;
    double tolerance_ = 0.0;
};

}  // namespace

WindowSet read_windows(const YamlMap& windows, const std::vector<double>& time) {
    windows.allow_only({"estimation", "validation", "warmup"});
    WindowSet set;
    if (windows.has("warmup")) {
        set.warmup = windows.number("warmup");
        if (set.warmup < 0) windows.fail("warmup", "the warm-up cannot be negative");
    }
    const WindowResolver resolver(windows.source(), time, set.warmup);
    set.estimation = resolver.list(windows, "estimation", true);
    set.validation = resolver.list(windows, "validation", false);
    return set;
}

}  // namespace tvid

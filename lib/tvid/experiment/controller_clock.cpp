#include "tvid/experiment/controller_clock.hpp"

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "tvid/util/text.hpp"

namespace tvid {
namespace {

// The median of the sample intervals of a time column (a gap does not move it).
double median_interval(const std::vector<double>& time) {
    std::vector<double> steps;
    steps.reserve(time.size());
    for (std::size_t i = 0; i + 1 < time.size(); ++i) steps.push_back(time[i + 1] - time[i]);
    if (steps.empty()) return 0.0;
    std::nth_element(steps.begin(), steps.begin() + static_cast<std::ptrdiff_t>(steps.size() / 2), steps.end());
    return steps[steps.size() / 2];
}

bool on_clock(double t, double period) {
    const double k = std::round(t / period);
    return std::abs(t - k * period) <= 1e-6 * period;
}

void check_clock(const YamlMap& entry, double period, const RecordingRead& r) {
    const std::vector<double>& time = r.table.column(r.time_column);
    const double dt = median_interval(time);
    const std::string file = r.table.file().string();
    if (dt > 0.0) {
        const double ratio = period / dt;
        if (ratio < 1.0 - 1e-6 || std::abs(ratio - std::round(ratio)) > 1e-6 * std::max(1.0, ratio))
            entry.fail("sample_period", number_text(period) + " s is not a whole number of sample intervals of " +
                                            file + " (" + number_text(dt) + " s): the controller samples at "
                                            "multiples of its period, and a simulation stops only at the recording's samples");
    }
    if (std::none_of(time.begin(), time.end(), [&](double t) { return on_clock(t, period); }))
        entry.fail("sample_period", "no sample of " + file + " falls on a multiple of " + number_text(period) +
                                        " s (its first is at t = " + number_text(time.front()) +
                                        " s): the controller samples at t = k * sample_period on the recording's clock");
}

}  // namespace

void refuse_sampled_warmup(const YamlMap& top, const Experiment& ex) {
    if (!has_sampled_elements(ex.network) || ex.initial_state != InitialStateKind::measured ||
        ex.angle_column.empty() || (ex.warmup <= 0 && ex.warmup_cycles <= 0))
        return;
    top.fail("initial_state", "a sampled controller (sample_period) cannot follow the crank-angle warm-up: the "
                              "shooting marches the warm-up apart from the window, and the controller's memory "
                              "restarts with each march; start from initial_state: steady or estimated, or drop the "
                              "warm-up");
}

void check_controller_clocks(const YamlMap& model, const DataSection& recorded) {
    if (!model.has("elements")) return;
    const YAML::Node list = model.get("elements");
    if (!list.IsSequence()) return;
    const std::string path = model.key_path("elements");
    for (std::size_t i = 0; i < list.size(); ++i) {
        const YamlMap entry(model.source(), list[i], path + "[" + std::to_string(i) + "]");
        if (!entry.has("sample_period")) continue;
        const double period = entry.number("sample_period");
        for (const RecordingRead& r : recorded.recordings) check_clock(entry, period, r);
    }
}

}  // namespace tvid

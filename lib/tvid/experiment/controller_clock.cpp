#include "tvid/experiment/controller_clock.hpp"

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "tvid/model/elements/position_controller.hpp"
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

// How far a sample may lie from the controller's instant: a small fraction of the
// recording's own interval, so that a logger's jittering clock (0.00099999 s between
// samples) is read as the clock it stands for.
constexpr double kClockJitter = 1e-3;

// Refuses a period that is not a whole number of the recording's intervals, or a recording
// none of whose samples falls on the controller's clock; returns the tolerance in seconds.
double check_clock(const YamlMap& entry, double period, const RecordingRead& r) {
    const std::vector<double>& time = r.table.column(r.time_column);
    const double dt = median_interval(time);
    const std::string file = r.table.file().string();
    const double tolerance = dt > 0.0 ? kClockJitter * dt : 1e-6 * period;
    if (dt > 0.0) {
        const double ratio = period / dt;
        if (ratio < 1.0 - kClockJitter || std::abs(ratio - std::round(ratio)) > kClockJitter)
            entry.fail("sample_period", number_text(period) + " s is not a whole number of sample intervals of " +
                                            file + " (" + number_text(dt) + " s): the controller samples at "
                                            "multiples of its period, and a simulation stops only at the recording's samples");
    }
    if (std::none_of(time.begin(), time.end(),
                     [&](double t) { return elements::PositionController::on_clock(t, period, tolerance); }))
        entry.fail("sample_period", "no sample of " + file + " falls on a multiple of " + number_text(period) +
                                        " s (its first is at t = " + number_text(time.front()) +
                                        " s): the controller samples at t = k * sample_period on the recording's clock");
    // Every instant of the controller within the recording is one of its samples: a clock
    // that drifts past the tolerance would skip instants silently. A gap in the recording
    // (more than 1.5 intervals) may hold instants with no sample; the part after it starts anew.
    double missing_at = -1.0;
    const auto check_part = [&](std::size_t from, std::size_t to) {  // samples [from, to)
        double next = std::ceil((time[from] - tolerance) / period);  // the next instant expected
        for (std::size_t i = from; i < to && missing_at < 0.0; ++i) {
            if (!elements::PositionController::on_clock(time[i], period, tolerance)) continue;
            const double k = std::round(time[i] / period);
            if (k > next) missing_at = next * period;
            next = k + 1.0;
        }
        if (missing_at < 0.0 && next * period < time[to - 1] - tolerance) missing_at = next * period;
    };
    std::size_t part = 0;
    for (std::size_t i = 1; i <= time.size() && missing_at < 0.0; ++i)
        if (i == time.size() || (dt > 0.0 && time[i] - time[i - 1] > 1.5 * dt)) {
            check_part(part, i);
            part = i;
        }
    if (missing_at >= 0.0)
        entry.fail("sample_period", "the controller's instant t = " + number_text(missing_at) + " s has no sample of " +
                                        file + " within " + number_text(tolerance) +
                                        " s (1e-3 of its interval): its clock drifts from k * " + number_text(period) + " s");
    return tolerance;
}

}  // namespace

double common_controller_period(const NetworkSpec& network) {
    double common = 0.0;
    for (const PositionControllerSpec& c : network.position_controllers) {
        if (!c.sampled()) continue;
        if (common == 0.0) {
            common = c.sample_period;
            continue;
        }
        // The smallest multiple of the common period so far that this period divides
        // (periods are whole numbers of the recording's interval, so one is near).
        for (int m = 1; m <= 1000; ++m) {
            const double ratio = m * common / c.sample_period;
            if (std::abs(ratio - std::round(ratio)) <= 1e-9 * ratio) {
                common *= m;
                break;
            }
        }
    }
    return common;
}

void refuse_sampled_warmup(const YamlMap& top, const Experiment& ex) {
    if (!has_sampled_elements(ex.network) || !initial_state_row(ex.initial_state).reads_measured_speed ||
        ex.angle_column.empty() || (ex.warmup <= 0 && ex.warmup_cycles <= 0))
        return;
    top.fail("initial_state", "a sampled controller (sample_period) cannot follow the crank-angle warm-up: the "
                              "shooting marches the warm-up apart from the window, and the controller's memory "
                              "restarts with each march; start from initial_state: steady or estimated, or drop the "
                              "warm-up");
}

void check_controller_clocks(const YamlMap& model, const DataSection& recorded, NetworkSpec& network) {
    if (!model.has("elements")) return;
    const YAML::Node list = model.get("elements");
    if (!list.IsSequence()) return;
    const std::string path = model.key_path("elements");
    for (std::size_t i = 0; i < list.size(); ++i) {
        const YamlMap entry(model.source(), list[i], path + "[" + std::to_string(i) + "]");
        if (!entry.has("sample_period")) continue;
        const double period = entry.number("sample_period");
        double tolerance = period;
        for (const RecordingRead& r : recorded.recordings) tolerance = std::min(tolerance, check_clock(entry, period, r));
        const std::string name = entry.has("name") ? entry.text("name") : std::string();
        for (PositionControllerSpec& c : network.position_controllers)
            if (c.name == name && c.sampled()) c.clock_tolerance = tolerance;
    }
}

}  // namespace tvid

#include "tvid/estimation/problem_definition.hpp"

#include <algorithm>
#include <cmath>
#include <utility>

namespace tvid {

namespace {
std::vector<double> scaled(const std::vector<double>& v, double scale) {
    std::vector<double> out(v);
    if (scale != 1.0)
        for (double& x : out) x *= scale;
    return out;
}

// A channel recorded `delay` seconds late, on the model's time: sample i takes the value
// at time[i] + delay, interpolated linearly between samples and held at the recording's
// ends (a channel logged by another device, with its own latency).
std::vector<double> undelayed(const std::vector<double>& v, const std::vector<double>& time, double delay) {
    if (delay == 0.0) return v;
    std::vector<double> out(v.size());
    std::size_t j = 0;  // time[j] <= t < time[j + 1] (time is strictly increasing)
    for (std::size_t i = 0; i < v.size(); ++i) {
        const double t = time[i] + delay;
        if (t <= time.front()) { out[i] = v.front(); continue; }
        if (t >= time.back()) { out[i] = v.back(); continue; }
        while (time[j + 1] <= t) ++j;  // t grows with i: j only moves on
        const double a = (t - time[j]) / (time[j + 1] - time[j]);
        out[i] = v[j] + a * (v[j + 1] - v[j]);
    }
    return out;
}

// The time derivative of a channel at its samples: central differences inside (second
// order on a non-uniform grid), one-sided at the ends.
std::vector<double> slope(const std::vector<double>& v, const std::vector<double>& time) {
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

std::vector<double> channel_values(const CsvTable& data, const std::vector<double>& time, const ChannelBinding& b) {
    return undelayed(scaled(data.column(b.column), b.scale), time, b.delay);
}
}  // namespace

// kSpeedLimitFactor times the largest speed the recording measures, or infinity.
double speed_limit(const ProblemDefinition& d, const Experiment& experiment) {
    double largest = 0.0;
    bool measured = false;
    const auto take = [&](const std::vector<double>& v) {
        for (double x : v) largest = std::max(largest, std::abs(x));
        measured = true;
    };
    for (std::size_t k = 0; k < d.measured.size(); ++k)
        if (d.network.outputs[static_cast<std::size_t>(d.output_indices[k])].kind == OutputKind::speed) take(d.measured[k]);
    for (const SpeedSourceSpec& s : d.network.speed_sources) {
        if (s.input < 0) continue;
        const std::size_t k = static_cast<std::size_t>(s.input);
        std::vector<double> v(d.inputs.samples());
        for (std::size_t i = 0; i < v.size(); ++i) v[i] = d.inputs.value(k, i);
        take(v);
    }
    if (experiment.initial_state == InitialStateKind::steady) {
        if (!d.steady_speed.empty()) take(d.steady_speed);
        else take({experiment.steady.speed});
    }
    if (!measured || !(largest > 0)) return std::numeric_limits<double>::infinity();
    return kSpeedLimitFactor * largest;
}

// The spread (standard deviation about the mean) of v over the scored samples of `windows`.
double spread(const std::vector<double>& v, const std::vector<Window>& windows) {
    double sum = 0.0, sum2 = 0.0, count = 0.0;
    for (const Window& w : windows)
        for (std::size_t i = std::max(w.first, w.start + 1); i <= w.last; ++i) {
            sum += v[i];
            count += 1.0;
        }
    if (count == 0.0) return 0.0;
    const double mean = sum / count;
    for (const Window& w : windows)
        for (std::size_t i = std::max(w.first, w.start + 1); i <= w.last; ++i) sum2 += (v[i] - mean) * (v[i] - mean);
    return std::sqrt(sum2 / count);
}

// Each output's factor in the cost: its weight, over its measured spread when normalized
// (an output that does not vary in the estimation windows keeps its weight alone).
void set_output_scales(ProblemDefinition& d, const Experiment& experiment) {
    const OutputNormalization n = experiment.estimation_settings.normalize;
    d.normalized = n == OutputNormalization::spread || (n == OutputNormalization::automatic && d.measured.size() > 1);
    for (std::size_t k = 0; k < d.measured.size(); ++k) {
        const double s = spread(d.measured[k], d.estimation);
        d.output_spread.push_back(s);
        const double w = experiment.outputs[k].weight;
        d.output_scale.push_back(d.normalized && s > 0 && std::isfinite(s) ? w / s : w);
        d.output_filter.push_back(experiment.outputs[k].scoring);
        d.filtered = d.filtered || experiment.outputs[k].scoring.active();
    }
}

ProblemDefinition problem_definition(const Experiment& experiment) {
    ProblemDefinition d;
    d.network = experiment.network;
    const CsvTable& data = experiment.data;
    std::vector<std::vector<double>> input_values, angle_values;
    const std::vector<double>& time = data.column(experiment.time_column);
    for (const ChannelBinding& in : experiment.inputs)
        (in.by_angle ? angle_values : input_values).push_back(channel_values(data, time, in));
    for (int k : experiment.network.input_rates)  // after the inputs, as NetworkSpec::input_rates places them
        input_values.push_back(slope(input_values[static_cast<std::size_t>(k)], time));
    d.inputs = InputChannels(time, std::move(input_values));
    if (!angle_values.empty()) d.angle_inputs = CrankAngleChannels(experiment.crank_angle, std::move(angle_values));
    for (const ChannelBinding& out : experiment.outputs) d.measured.push_back(channel_values(data, time, out));
    d.output_indices = experiment.output_indices;
    d.parameters = experiment.parameters;
    d.estimation = experiment.estimation;
    d.initial_state = experiment.initial_state;
    d.initial_speed_output = experiment.initial_speed_output;
    d.steady = experiment.steady;
    if (!d.steady.speed_column.empty()) d.steady_speed = data.column(d.steady.speed_column);
    d.crank_angle = experiment.crank_angle;
    d.angle_node = experiment.angle_node;
    d.simulation = experiment.simulation;
    d.speed_limit = speed_limit(d, experiment);
    d.cost = experiment.estimation_settings.cost;
    set_output_scales(d, experiment);
    d.jacobian = experiment.estimation_settings.jacobian;
    return d;
}

}  // namespace tvid

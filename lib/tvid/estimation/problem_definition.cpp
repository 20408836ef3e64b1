#include "tvid/estimation/problem_definition.hpp"

#include "tvid/channels/channel_delay.hpp"
#include "tvid/experiment/window_recording.hpp"
#include "tvid/model/parameter_units.hpp"
#include "tvid/model/steady_motion.hpp"

#include <algorithm>
#include <cmath>
#include <string_view>
#include <utility>

namespace tvid {

namespace {
std::vector<double> scaled(const std::vector<double>& v, double scale) {
    std::vector<double> out(v);
    if (scale != 1.0)
        for (double& x : out) x *= scale;
    return out;
}

// A channel's delay: its number, or its parameter's init.
double delay_value(const ChannelBinding& b, const Experiment& experiment) {
    return b.delay.is_parameter() ? experiment.parameters[static_cast<std::size_t>(b.delay.parameter)].init
                                  : b.delay.constant;
}

// Each recording's samples read `delay` later within that recording.
std::vector<double> shifted(const std::vector<double>& v, const std::vector<double>& time,
                            const std::vector<RowSpan>& recordings, double delay) {
    std::vector<double> out;
    delay_channel(v, time, recordings, delay, out);
    return out;
}

}  // namespace

// The channels as recorded (unit-scaled, not shifted by any delay): what is derived from
// a channel (the outputs' spreads, the speed limit) reads these, so it depends on no
// delay, neither a number nor a parameter's init or candidate value. A delay moves
// samples; the spread over a window must not change with it.
namespace {
struct Unshifted {
    std::vector<std::vector<double>> inputs;   ///< the time inputs, in InputChannels order (no rates)
    std::vector<std::vector<double>> outputs;  ///< the measured outputs
};
}  // namespace

// Each node's limit: kSpeedLimitFactor times the largest speed the recording measures of
// a node it is tied to, through the gear ratios between them (a ball screw's 1250 rad/m
// turns a linear speed in m/s into the motor's in rad/s; a gearhead multiplies by its
// ratio); infinity for a node tied to no measured speed, or when nothing measures one.
std::vector<double> node_speed_limits(const ProblemDefinition& d, const Experiment& experiment, const Unshifted& u) {
    const std::size_t n = d.network.nodes.size();
    std::vector<double> largest(n, 0.0);
    const auto take = [&](int node, const std::vector<double>& v) {
        if (node < 0 || static_cast<std::size_t>(node) >= n) return;
        for (double x : v) largest[static_cast<std::size_t>(node)] = std::max(largest[static_cast<std::size_t>(node)], std::abs(x));
    };
    for (std::size_t k = 0; k < d.measured.size(); ++k)
        if (const OutputSpec& o = d.network.outputs[static_cast<std::size_t>(d.output_indices[k])]; output_is_speed(o.kind))
            take(o.node, u.outputs[k]);
    // The measured speeds the model reads (a speed source's channel).
    for (const auto& source : d.network.speed_sources)
        if (source.input >= 0 && static_cast<std::size_t>(source.input) < u.inputs.size())
            take(source.node, u.inputs[static_cast<std::size_t>(source.input)]);
    if (experiment.initial_state == InitialStateKind::steady) {
        const int node = experiment.steady.node;
        if (d.steady_speed_input >= 0) take(node, u.inputs[static_cast<std::size_t>(d.steady_speed_input)]);
        else if (d.steady_speed_output >= 0) take(node, u.outputs[static_cast<std::size_t>(d.steady_speed_output)]);
        else if (!d.steady_speed.empty()) take(node, d.steady_speed);
        else take(node, {experiment.steady.speed});
    }
    std::vector<double> p;
    for (const ParameterSetting& s : d.parameters) p.push_back(s.init);
    // The largest speed each node turns at, by the measured ones.
    const std::vector<double> scale = speeds_through_rigid_ties(d.network, p, largest);
    std::vector<double> limits(n, std::numeric_limits<double>::infinity());
    for (std::size_t j = 0; j < n; ++j)
        if (scale[j] > 0 && std::isfinite(scale[j])) limits[j] = kSpeedLimitFactor * scale[j];
    return limits;
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
void set_output_scales(ProblemDefinition& d, const Experiment& experiment, const Unshifted& u) {
    const OutputNormalization n = experiment.estimation_settings.normalize;
    d.normalized = n == OutputNormalization::spread || (n == OutputNormalization::automatic && d.measured.size() > 1);
    for (std::size_t k = 0; k < d.measured.size(); ++k) {
        const double s = spread(u.outputs[k], d.estimation);
        d.output_spread.push_back(s);
        const double w = experiment.outputs[k].weight;
        d.output_scale.push_back(d.normalized && s > 0 && std::isfinite(s) ? w / s : w);
        d.output_filter.push_back(experiment.outputs[k].scoring);
        d.filtered = d.filtered || experiment.outputs[k].scoring.active();
    }
}

// The time inputs, shifted by their delays, then the rates of those the model
// differentiates (a rate of a delay parameter's input is the recording's rate, shifted).
static void read_time_inputs(ProblemDefinition& d, const Experiment& experiment, const std::vector<double>& time,
                             Unshifted& unshifted) {
    std::vector<std::vector<double>> values, recorded;
    std::vector<int> delay_parameter;
    for (const ChannelBinding& in : experiment.inputs) {
        if (in.by_angle) continue;
        recorded.push_back(scaled(experiment.data.column(in.column), in.scale));
        values.push_back(shifted(recorded.back(), time, d.recordings, delay_value(in, experiment)));
        unshifted.inputs.push_back(recorded.back());
        delay_parameter.push_back(in.delay.parameter);
        d.input_noise.push_back(in.noise);
    }
    for (int k : experiment.network.input_rates) {  // after the inputs, as NetworkSpec::input_rates places them
        const auto from = static_cast<std::size_t>(k);
        const int p = delay_parameter[from];
        if (p < 0) {
            values.push_back(sample_slopes(values[from], time, d.recordings));
        } else {
            recorded.push_back(sample_slopes(recorded[from], time, d.recordings));
            values.push_back(
                shifted(recorded.back(), time, d.recordings, experiment.parameters[static_cast<std::size_t>(p)].init));
        }
        delay_parameter.push_back(p);
    }
    for (std::size_t k = 0; k < values.size(); ++k)
        if (delay_parameter[k] >= 0) {
            std::vector<double> slope = sample_slopes(recorded[k], time, d.recordings);
            d.delayed_inputs.push_back({k, delay_parameter[k], std::move(recorded[k]), std::move(slope)});
        }
    d.input_noise.resize(values.size(), 0.0);  // the rates follow their inputs' noise (analysis/input_noise.hpp)
    d.inputs = InputChannels(time, std::move(values));
}

// A steady start's speed column, read as the first channel bound to it reads it (unit,
// scale, delay), else as recorded.
static void read_steady_speed(ProblemDefinition& d, const Experiment& experiment) {
    const std::string& column = d.steady.speed_column;
    int input = 0;
    for (const ChannelBinding& in : experiment.inputs) {
        if (in.by_angle) continue;
        if (in.column == column) {
            d.steady_speed_input = input;
            return;
        }
        ++input;
    }
    for (std::size_t k = 0; k < experiment.outputs.size(); ++k)
        if (experiment.outputs[k].column == column) {
            d.steady_speed_output = static_cast<int>(k);
            return;
        }
    d.steady_speed = experiment.data.column(column);
}

ProblemDefinition problem_definition(const Experiment& experiment) {
    ProblemDefinition d;
    d.network = experiment.network;
    d.recordings = recording_spans(experiment);
    const CsvTable& data = experiment.data;
    const std::vector<double>& time = data.column(experiment.time_column);
    Unshifted unshifted;
    read_time_inputs(d, experiment, time, unshifted);
    std::vector<std::vector<double>> angle_values;
    for (const ChannelBinding& in : experiment.inputs)
        if (in.by_angle)
            angle_values.push_back(
                shifted(scaled(data.column(in.column), in.scale), time, d.recordings, delay_value(in, experiment)));
    if (!angle_values.empty())
        d.angle_inputs = CrankAngleChannels::end_to_end(experiment.crank_angle, angle_values, d.recordings);
    for (const ChannelBinding& out : experiment.outputs) {
        std::vector<double> recorded = scaled(data.column(out.column), out.scale);
        d.measured.push_back(shifted(recorded, time, d.recordings, delay_value(out, experiment)));
        unshifted.outputs.push_back(recorded);
        d.output_delay.push_back(out.delay.parameter);
        if (out.delay.is_parameter()) {
            std::vector<double> slope = sample_slopes(recorded, time, d.recordings);
            d.delayed_outputs.push_back({d.measured.size() - 1, out.delay.parameter, std::move(recorded), std::move(slope)});
        }
    }
    d.output_indices = experiment.output_indices;
    d.parameters = experiment.parameters;
    d.estimation = experiment.estimation;
    d.initial_state = experiment.initial_state;
    d.initial_speed_output = experiment.initial_speed_output;
    d.steady = experiment.steady;
    d.estimated.on = experiment.estimated_start.on;
    d.estimated.validation = experiment.estimated_start.validation;
    d.estimated.of_window.resize(d.estimated.on ? d.estimation.size() : 0);
    for (const NetworkSpec::StartCoordinate& c : d.network.start_coordinates)
        if (c.window < d.estimated.of_window.size()) {
            d.estimated.of_window[c.window].push_back(c);
            if (c.window == 0) d.estimated.states.push_back(c.state);
        }
    if (!d.steady.speed_column.empty()) read_steady_speed(d, experiment);
    d.crank_angle = experiment.crank_angle;
    d.angle_node = experiment.angle_node;
    d.simulation = experiment.simulation;
    d.speed_limits = node_speed_limits(d, experiment, unshifted);
    d.cost = experiment.estimation_settings.cost;
    set_output_scales(d, experiment, unshifted);
    d.jacobian = experiment.estimation_settings.jacobian;
    return d;
}

}  // namespace tvid

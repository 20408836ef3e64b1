#include "tvid/estimation/problem_definition.hpp"

#include <utility>

namespace tvid {

namespace {
std::vector<double> scaled(const std::vector<double>& v, double scale) {
    std::vector<double> out(v);
    if (scale != 1.0)
        for (double& x : out) x *= scale;
    return out;
}
}  // namespace

ProblemDefinition problem_definition(const Experiment& experiment) {
    ProblemDefinition d;
    d.network = experiment.network;
    const CsvTable& data = experiment.data;
    std::vector<std::vector<double>> input_values, angle_values;
    for (const ChannelBinding& in : experiment.inputs)
        (in.by_angle ? angle_values : input_values).push_back(scaled(data.column(in.column), in.scale));
    d.inputs = InputChannels(data.column(experiment.time_column), std::move(input_values));
    if (!angle_values.empty()) d.angle_inputs = CrankAngleChannels(experiment.crank_angle, std::move(angle_values));
    for (const ChannelBinding& out : experiment.outputs) d.measured.push_back(scaled(data.column(out.column), out.scale));
    d.output_indices = experiment.output_indices;
    d.parameters = experiment.parameters;
    d.estimation = experiment.estimation;
    d.initial_state = experiment.initial_state;
    d.initial_speed_output = experiment.initial_speed_output;
    d.crank_angle = experiment.crank_angle;
    d.angle_node = experiment.angle_node;
    d.simulation = experiment.simulation;
    d.cost = experiment.estimation_settings.cost;
    d.jacobian = experiment.estimation_settings.jacobian;
    return d;
}

}  // namespace tvid

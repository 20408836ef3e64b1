#include "tvid/experiment/node_speeds.hpp"

#include <algorithm>
#include <cmath>

#include "tvid/model/steady_motion.hpp"

namespace tvid {

std::vector<std::vector<double>> measured_node_speeds(const Experiment& ex) {
    std::vector<std::vector<double>> speed(ex.network.nodes.size());
    const auto take = [&](int node, const std::vector<double>& column, double scale) {
        if (node < 0 || static_cast<std::size_t>(node) >= speed.size() || !speed[static_cast<std::size_t>(node)].empty())
            return;
        std::vector<double>& v = speed[static_cast<std::size_t>(node)];
        v.reserve(column.size());
        for (double x : column) v.push_back(x * scale);
    };
    for (std::size_t k = 0; k < ex.outputs.size(); ++k) {
        const OutputSpec& o = ex.network.outputs[static_cast<std::size_t>(ex.output_indices[k])];
        if (output_is_speed(o.kind)) take(o.node, ex.data.column(ex.outputs[k].column), ex.outputs[k].scale);
    }
    for (const SpeedSourceSpec& s : ex.network.speed_sources)
        if (s.input >= 0 && static_cast<std::size_t>(s.input) < ex.inputs.size() && !s.scale.is_parameter())
            take(s.node, ex.data.column(ex.inputs[static_cast<std::size_t>(s.input)].column),
                 ex.inputs[static_cast<std::size_t>(s.input)].scale * s.scale.constant);
    return speed;
}

double largest_finite(const std::vector<double>& v) {
    double largest = 0.0;
    for (double x : v)
        if (std::isfinite(x)) largest = std::max(largest, std::abs(x));
    return largest;
}

std::vector<double> node_speed_scales(const Experiment& ex, const std::vector<double>& p) {
    const std::vector<std::vector<double>> speed = measured_node_speeds(ex);
    std::vector<double> largest(speed.size(), 0.0);
    for (std::size_t i = 0; i < speed.size(); ++i) largest[i] = largest_finite(speed[i]);
    return speeds_through_rigid_ties(ex.network, p, largest);
}

}  // namespace tvid

#include "tvid/experiment/estimated_start.hpp"

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "tvid/experiment/node_speeds.hpp"
#include "tvid/model/network_model.hpp"
#include "tvid/model/steady_motion.hpp"
#include "tvid/util/input_error.hpp"

namespace tvid {

namespace {

// Which nodes a speed source turns: their speed comes from its channel, not the state.
std::vector<char> prescribed_speeds(NetworkModel<double>& model) {
    const std::size_t n = model.node_count();
    std::vector<double> x(2 * n, std::nan("")), u(model.input_count() + model.spec().input_rates.size(), 1.0);
    for (std::size_t i = 0; i < n; ++i) x[i] = 0.0;
    const double* seen = model.speeds_seen(x.data(), u.data());
    std::vector<char> prescribed(n, 0);
    for (std::size_t i = 0; i < n; ++i) prescribed[i] = std::isfinite(seen[i]) ? 1 : 0;
    return prescribed;
}

// Whether turning the nodes of a rigid motion (rigid.ratio, on the nodes it ties) all
// together changes any node's acceleration or any output: false for a line that nothing
// ties to ground and no output reads an angle of. Tried at an arbitrary twisted, turning
// state with every input at 1 (a rigid rotation leaves the twists, so a line invariant
// under it is so at every state).
bool rotation_is_seen(NetworkModel<double>& model, const RigidMotion& rigid) {
    const std::size_t n = model.node_count();
    std::vector<double> x(2 * n), u(model.input_count() + model.spec().input_rates.size(), 1.0);
    for (std::size_t i = 0; i < n; ++i) {
        x[i] = 0.1 * std::sin(1.0 + static_cast<double>(i));
        x[n + i] = 3.0 + std::cos(2.0 + static_cast<double>(i));
    }
    const auto observe = [&](std::vector<double>& out) {
        out.resize(2 * n + model.spec().outputs.size());
        model.derivative(x.data(), u.data(), out.data());
        for (std::size_t k = 0; k < model.spec().outputs.size(); ++k) out[2 * n + k] = model.output(k, x.data(), u.data());
    };
    std::vector<double> before, after;
    observe(before);
    for (std::size_t i = 0; i < n; ++i)
        if (rigid.tied[i]) x[i] += 0.7 * rigid.ratio[i];
    observe(after);
    for (std::size_t k = 0; k < before.size(); ++k)
        if (!(std::abs(after[k] - before[k]) <= 1e-9 * (1.0 + std::abs(before[k])))) return true;
    return false;
}

// `validation: estimated`: a validation window without a warm-up fits its start on the
// samples after its first (a tenth of it, at least two per estimated coordinate), and they
// become its lead-in, simulated but not scored (WindowStarts::estimated_start_samples): a
// start fitted to the very samples it is judged on would score any model well on a short
// window. A window that leaves fewer samples to score than its start is fitted on is refused.
void hold_out_start_samples(Experiment& ex, std::size_t coordinates) {
    for (Window& w : ex.validation) {
        if (w.first > w.start) continue;  // its warm-up holds the start's samples
        const std::size_t fitted = std::max<std::size_t>((w.last - w.start) / 10, 2 * coordinates);
        if (w.last < w.start + 2 * fitted)
            throw InputError(w.where.file, w.where.line, w.where.key,
                             "validation window '" + w.label + "' holds " + std::to_string(w.last - w.start + 1) +
                                 " samples; with initial_state.validation: estimated its start (" +
                                 std::to_string(coordinates) + " coordinates) is fitted on the " + std::to_string(fitted) +
                                 " after its first, which are not scored, and fewer than " + std::to_string(fitted) +
                                 " would be left to score: make it at least " + std::to_string(2 * fitted + 1) +
                                 " samples long, or give windows.warmup");
        w.first = w.start + fitted + 1;
    }
}

}  // namespace

void define_estimated_starts(Experiment& ex) {
    const std::size_t n = ex.network.nodes.size();
    std::vector<char> estimate_angle(n, 1), estimate_speed(n, 1);
    std::vector<double> p;
    for (const ParameterSetting& s : ex.parameters) p.push_back(s.init);
    {
        NetworkModel<double> model(ex.network);
        model.set_parameters(p.data());
        const std::vector<char> prescribed = prescribed_speeds(model);
        for (std::size_t i = 0; i < n; ++i) estimate_speed[i] = prescribed[i] ? 0 : 1;
        // A node an ideal gear ties to its group's root moves with it: the root's coordinates hold the group's.
        for (std::size_t i = 0; i < n; ++i)
            if (model.tied_to_other(i)) estimate_speed[i] = estimate_angle[i] = 0;
        // One angle per rigid rotation nothing sees stays the recipe's: its first node's.
        std::vector<char> placed(n, 0);
        for (std::size_t r = 0; r < n; ++r) {
            if (placed[r]) continue;
            const RigidMotion rigid = rigid_motion(ex.network, p, static_cast<int>(r));
            for (std::size_t i = 0; i < n; ++i) placed[i] = placed[i] || rigid.tied[i];
            placed[r] = 1;
            if (rigid.problem.empty() && !rotation_is_seen(model, rigid)) estimate_angle[r] = 0;
        }
    }
    const std::vector<double> speed_scale = node_speed_scales(ex, p);
    // Where no measured speed reaches a node: the largest of the nodes of its kind (rad/s or m/s).
    double largest_rotating = 0.0, largest_linear = 0.0;
    for (std::size_t i = 0; i < n; ++i) {
        double& of_kind = ex.network.nodes[i].linear ? largest_linear : largest_rotating;
        of_kind = std::max(of_kind, speed_scale[i]);
    }
    for (std::size_t w = 0; w < ex.estimation.size(); ++w)
        for (std::size_t state = 0; state < 2 * n; ++state) {
            const std::size_t node = state % n;
            const bool angle = state < n;
            if (!(angle ? estimate_angle[node] : estimate_speed[node])) continue;
            const NodeSpec& spec = ex.network.nodes[node];
            ParameterSetting s;
            s.name = "start" + std::to_string(w + 1) + "." + spec.name + (angle ? (spec.linear ? ".position" : ".angle")
                                                                                 : ".speed");
            if (ex.network.parameter_index(s.name) >= 0)
                throw InputError(ex.estimated_start.where.file, ex.estimated_start.where.line, ex.estimated_start.where.key,
                                 "the estimated start's parameter " + s.name + " is also a model parameter: rename it");
            s.init = 0.0;  // a correction to the recipe's seed
            const double of_kind = spec.linear ? largest_linear : largest_rotating;
            const double range = angle                    ? kStartAngleRange
                                  : speed_scale[node] > 0 ? kStartSpeedShare * speed_scale[node]
                                                          : std::max(kStartSpeedRange, kStartSpeedShare * of_kind);
            s.range = std::make_pair(-range, range);
            s.where = ex.estimated_start.where;
            const int index = static_cast<int>(ex.network.parameter_names.size());
            ex.network.parameter_names.push_back(s.name);
            ex.network.start_coordinates.push_back({index, w, state});
            ex.parameters.push_back(std::move(s));
        }
    if (ex.estimated_start.validation && !ex.estimation.empty())
        hold_out_start_samples(ex, ex.network.start_coordinates.size() / ex.estimation.size());
}

}  // namespace tvid

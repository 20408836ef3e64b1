#include "tvid/experiment/smoothing_speeds.hpp"

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "tvid/experiment/node_speeds.hpp"
#include "tvid/util/text.hpp"

namespace tvid {

namespace {

// The channel's noise: the median absolute sample-to-sample difference over 0.6745·√2 (a
// standard deviation for Gaussian noise on a signal smooth at the sample rate).
double sample_noise(const std::vector<double>& v) {
    std::vector<double> step;
    for (std::size_t i = 1; i < v.size(); ++i)
        if (std::isfinite(v[i]) && std::isfinite(v[i - 1])) step.push_back(std::abs(v[i] - v[i - 1]));
    if (step.empty()) return 0.0;
    const auto middle = step.begin() + static_cast<std::ptrdiff_t>(step.size() / 2);
    std::nth_element(step.begin(), middle, step.end());
    return *middle / (0.6745 * std::sqrt(2.0));
}

// Of the samples in motion (|v| above 3 times the channel's noise: a stuck axis reads its
// noise, and the smoothed law holds it as it should), the share within `width` of zero;
// negative when v is empty or never moves.
double share_within(const std::vector<double>& v, double width) {
    const double moving = 3.0 * sample_noise(v);
    double inside = 0.0, count = 0.0;
    for (double x : v) {
        if (!std::isfinite(x) || !(std::abs(x) > moving)) continue;
        count += 1.0;
        if (std::abs(x) < width) inside += 1.0;
    }
    return count > 0 ? inside / count : -1.0;
}

}  // namespace

void choose_smoothing_speeds(Experiment& ex) {
    NetworkSpec& net = ex.network;
    const std::vector<std::vector<double>> speed = measured_node_speeds(ex);
    std::vector<double> p;
    for (const ParameterSetting& s : ex.parameters) p.push_back(s.init);
    const std::vector<double> scale = node_speed_scales(ex, p);
    const auto unit_of = [&](int node) {
        return output_kind_unit(OutputKind::speed, net.nodes[static_cast<std::size_t>(node)].linear);
    };
    const auto node_name = [&](int node) { return net.nodes[static_cast<std::size_t>(node)].name; };

    // One element across nodes a and b (b: ground): its speed per sample where measured, the
    // largest speed across it, and in what words.
    const auto choose = [&](const std::string& name, const char* kind, int a, int b, Field& smoothing, bool given,
                            double fallback) {
        SmoothingChoice c;
        c.element = name;
        c.kind = kind;
        c.unit = unit_of(a);
        c.given = given;
        std::vector<double> across;  // the measured speed across the element, per sample
        std::string where;
        if (b == kGround) {
            across = speed[static_cast<std::size_t>(a)];
            c.largest_speed = scale[static_cast<std::size_t>(a)];
            where = "node " + node_name(a) + (across.empty() && c.largest_speed > 0 ? ", through the gear ratios" : "");
        } else if (!speed[static_cast<std::size_t>(a)].empty() && !speed[static_cast<std::size_t>(b)].empty()) {
            const auto& va = speed[static_cast<std::size_t>(a)];
            const auto& vb = speed[static_cast<std::size_t>(b)];
            across.resize(std::min(va.size(), vb.size()));
            for (std::size_t i = 0; i < across.size(); ++i) across[i] = va[i] - vb[i];
            c.largest_speed = largest_finite(across);
            where = "nodes " + node_name(a) + " and " + node_name(b) + ", relative";
        }
        const std::string largest_text = number_text(c.largest_speed) + " " + c.unit;
        if (given) {
            c.speed = smoothing.is_parameter() ? p[static_cast<std::size_t>(smoothing.parameter)] : smoothing.constant;
            c.basis = "given";
        } else if (c.largest_speed > 0 && std::isfinite(c.largest_speed)) {
            c.speed = kSmoothingShareOfSpeed * c.largest_speed;
            smoothing = Field::value(c.speed);
            c.basis = "1 % of " + largest_text + ", the largest speed the recordings show at " + where;
        } else {
            c.speed = fallback;
            c.basis = b == kGround ? "the fixed default: no recorded speed reaches node " + node_name(a)
                                   : "the fixed default: the recordings do not measure both nodes " + node_name(a) +
                                         " and " + node_name(b);
        }
        c.share_within = share_within(across, kSmoothingShareSpeeds * c.speed);
        ex.smoothing.push_back(std::move(c));
    };
    for (FrictionSpec& f : net.frictions)
        if (f.dry || f.asymmetric)
            choose(f.name, "friction", f.a, f.b, f.smoothing_speed, f.smoothing_given,
                   elements::Friction::kDefaultSmoothingSpeed);
    for (RoadLoadSpec& r : net.road_loads)
        choose(r.name, "road_load", r.node, kGround, r.smoothing_speed, r.smoothing_given,
               elements::RoadLoad::kDefaultSmoothingSpeed);
}

}  // namespace tvid

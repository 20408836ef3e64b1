#include "tvid/model/parameter_units.hpp"

#include <algorithm>

#include "tvid/model/presets.hpp"

namespace tvid {

namespace {

void assign(std::vector<std::string>& units, const Field& field, const std::string& unit) {
    if (!field.is_parameter()) return;
    std::string& u = units[static_cast<std::size_t>(field.parameter)];
    if (u.empty()) u = unit;
}

void replace_all(std::string& text, const std::string& from, const std::string& to) {
    for (std::size_t at = text.find(from); at != std::string::npos; at = text.find(from, at + to.size()))
        text.replace(at, from.size(), to);
}

bool is_linear(const NetworkSpec& network, int node) {
    return node >= 0 && network.nodes[static_cast<std::size_t>(node)].linear;
}

// A unit as node `node` reads it.
std::string unit_on(const NetworkSpec& network, int node, const std::string& unit) {
    return is_linear(network, node) ? translational_unit(unit) : unit;
}

}  // namespace

std::string translational_unit(const std::string& rotational) {
    if (rotational == "1/(kg m^2)") return "1/kg";
    std::string u = rotational;
    replace_all(u, "kg m^2", "kg");
    replace_all(u, "N m", "N");
    replace_all(u, "rad", "m");
    return u;
}

std::string output_unit(const NetworkSpec& network, const OutputSpec& output) {
    int node = output.node;
    if (!output_reads_node(output.kind)) {
        // An element's torque: on its first node, or on its output shaft b (a gear mesh's side: output).
        for_each_element(network, [&](auto kind, const auto& e) {
            using Kind = decltype(kind);
            if (ElementRow<Kind>::kind != output.element.kind) return;
            if (&e != &ElementRow<Kind>::list(network)[static_cast<std::size_t>(output.element.index)]) return;
            node = element_node<Kind>(e);
            if constexpr (acts_between_nodes<Kind>)
                if (output.side == TorqueSide::output) node = e.b;
        });
    }
    return output_kind_unit(output.kind, is_linear(network, node));
}

namespace {

/// f(Kind, element) for the first element that reads the network's input by time `input`.
template <class F>
void with_input_reader(const NetworkSpec& network, std::size_t input, F&& f) {
    bool found = false;
    for_each_element(network, [&](auto kind, const auto& e) {
        using Kind = decltype(kind);
        if (!found && Kind::channel.unit != nullptr && !Kind::channel.by_angle && Kind::channel_of(e) >= 0 &&
            static_cast<std::size_t>(Kind::channel_of(e)) == input) {
            found = true;
            f(kind, e);
        }
    });
}

}  // namespace

std::string input_unit(const NetworkSpec& network, std::size_t input) {
    std::string unit;
    with_input_reader(network, input, [&](auto kind, const auto& e) {
        unit = unit_on(network, element_node<decltype(kind)>(e), decltype(kind)::channel.unit);
    });
    return unit;
}

int input_node(const NetworkSpec& network, std::size_t input) {
    int node = -1;
    with_input_reader(network, input, [&](auto kind, const auto& e) { node = element_node<decltype(kind)>(e); });
    return node;
}

std::vector<std::string> parameter_units(const NetworkSpec& network) {
    std::vector<std::string> units(network.parameter_names.size());
    for (int p : network.delay_parameters) assign(units, Field::param(p), "s");
    const std::size_t n = network.nodes.size();
    for (const NetworkSpec::StartCoordinate& c : network.start_coordinates) {
        const NodeSpec& node = network.nodes[c.state % n];
        assign(units, Field::param(c.parameter),
               output_kind_unit(c.state < n ? OutputKind::angle : OutputKind::speed, node.linear));
    }
    if (const PresetInfo* preset = find_preset(network.preset);
        preset && preset->parameter_units.size() <= network.parameter_names.size()) {
        std::copy(preset->parameter_units.begin(), preset->parameter_units.end(), units.begin());  // then the delays
        return units;
    }
    for (const NodeSpec& node : network.nodes) {
        const std::string unit = node.inverse ? "1/(kg m^2)" : "kg m^2";
        assign(units, node.inertia, node.linear ? translational_unit(unit) : unit);
    }
    for_each_element(network, [&](auto kind, const auto& e) {
        decltype(kind)::for_each_field(
            [&](const FieldInfo& info, const Field& field) {
                if (info.in_use) assign(units, field, unit_on(network, element_node<decltype(kind)>(e), info.unit));
            },
            e);
    });
    for (const OutputSpec& output : network.outputs) {
        assign(units, output.offset, output_unit(network, output));
        assign(units, output.gain, "1");
    }
    return units;
}

}  // namespace tvid

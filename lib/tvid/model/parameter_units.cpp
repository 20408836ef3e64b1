#include "tvid/model/parameter_units.hpp"

#include <algorithm>

#include "tvid/model/presets.hpp"

namespace tvid {

namespace {

void assign(std::vector<std::string>& units, const Field& field, const char* unit) {
    if (!field.is_parameter()) return;
    std::string& u = units[static_cast<std::size_t>(field.parameter)];
    if (u.empty()) u = unit;
}

}  // namespace

const char* output_unit(const OutputSpec& output) { return output_kind_unit(output.kind); }

const char* input_unit(const NetworkSpec& network, std::size_t input) {
    const char* unit = "";
    for_each_element(network, [&](auto kind, const auto& e) {
        using Kind = decltype(kind);
        if (*unit == '\0' && Kind::channel.unit != nullptr && !Kind::channel.by_angle &&
            Kind::channel_of(e) >= 0 && static_cast<std::size_t>(Kind::channel_of(e)) == input)
            unit = Kind::channel.unit;
    });
    return unit;
}

std::vector<std::string> parameter_units(const NetworkSpec& network) {
    std::vector<std::string> units(network.parameter_names.size());
    for (int p : network.delay_parameters) assign(units, Field::param(p), "s");
    if (const PresetInfo* preset = find_preset(network.preset);
        preset && preset->parameter_units.size() <= network.parameter_names.size()) {
        std::copy(preset->parameter_units.begin(), preset->parameter_units.end(), units.begin());  // then the delays
        return units;
    }
    for (const NodeSpec& node : network.nodes) assign(units, node.inertia, node.inverse ? "1/(kg m^2)" : "kg m^2");
    for_each_element_field(network, [&](const FieldInfo& info, const Field& field) { assign(units, field, info.unit); });
    for (const OutputSpec& output : network.outputs) {
        assign(units, output.offset, output_unit(output));
        assign(units, output.gain, "1");
    }
    return units;
}

}  // namespace tvid

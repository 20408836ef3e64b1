#include "tvid/model/parameter_units.hpp"

#include <algorithm>
#include <cstring>

#include "tvid/model/presets.hpp"

namespace tvid {

namespace {

// A field's unit from what it is (FieldInfo's role) or, for fields without a sign rule,
// from its key.
const char* field_unit(const FieldInfo& info) {
    const char* role = info.role ? info.role : "";
    if (std::strstr(role, "stiffness")) return "N m/rad";
    if (std::strstr(role, "damping coefficient") || std::strstr(role, "friction coefficient")) return "N m s/rad";
    if (std::strstr(role, "backlash")) return "rad";
    if (std::strstr(role, "steepness")) return "1/rad";
    if (std::strstr(role, "cylinder dimension")) return "m";
    if (std::strstr(role, "mass")) return "kg";
    if (std::strstr(role, "pressure")) return "Pa";
    const std::string key = info.name;
    if (key == "ratio" || key == "scale" || key == "gain") return "1";
    if (key == "amplitude" || key == "offset") return "N m";
    if (key == "phase") return "rad";
    if (key == "speed") return "rad/s";
    return "";
}

void assign(std::vector<std::string>& units, const Field& field, const char* unit) {
    if (!field.is_parameter()) return;
    std::string& u = units[static_cast<std::size_t>(field.parameter)];
    if (u.empty()) u = unit;
}

}  // namespace

const char* output_unit(const OutputSpec& output) {
    switch (output.kind) {
        case OutputKind::speed: return "rad/s";
        case OutputKind::angle: return "rad";
        default: return "N m";
    }
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
    for_each_element_field(network, [&](const FieldInfo& info, const Field& field) { assign(units, field, field_unit(info)); });
    for (const OutputSpec& output : network.outputs) {
        assign(units, output.offset, output_unit(output));
        assign(units, output.gain, "1");
    }
    return units;
}

}  // namespace tvid

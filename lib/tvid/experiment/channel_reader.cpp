#include "tvid/experiment/channel_reader.hpp"

#include "tvid/io/atomic_file.hpp"
#include "tvid/util/text.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "tvid/experiment/model_reader.hpp"
#include "tvid/model/parameter_units.hpp"
#include "tvid/util/input_error.hpp"

namespace tvid {

namespace {

constexpr double kSmallestWeight = 1e-8, kLargestWeight = 1e8;  // an output's weight

struct UnitFactor {
    const char* unit;
    double factor;
    const char* si;  ///< the SI unit it converts to: the quantity it measures
};

constexpr double kPi = std::numbers::pi;
const UnitFactor kUnits[] = {
    {"Pa", 1.0, "Pa"},        {"kPa", 1e3, "Pa"},          {"MPa", 1e6, "Pa"},           {"bar", 1e5, "Pa"},
    {"N m", 1.0, "N m"},      {"Nm", 1.0, "N m"},          {"kN m", 1e3, "N m"},         {"kNm", 1e3, "N m"},
    {"rad", 1.0, "rad"},      {"deg", kPi / 180.0, "rad"}, {"rad/s", 1.0, "rad/s"},      {"rpm", 2.0 * kPi / 60.0, "rad/s"},
    {"deg/s", kPi / 180.0, "rad/s"}, {"1", 1.0, "1"},
    // a translational node's channels (motion: linear)
    {"N", 1.0, "N"},          {"kN", 1e3, "N"},            {"m", 1.0, "m"},              {"mm", 1e-3, "m"},
    {"m/s", 1.0, "m/s"},      {"mm/s", 1e-3, "m/s"},
};

// What each SI unit of the table measures, in words.
struct SiQuantity {
    const char* si;
    const char* words;
};
const SiQuantity kQuantities[] = {
    {"Pa", "a pressure"}, {"N m", "a torque"},         {"N", "a force"},           {"rad", "an angle"},
    {"m", "a position"},  {"rad/s", "an angular speed"}, {"m/s", "a linear speed"}, {"1", "a pure number"},
};

std::string quantity_of(const std::string& si) {
    for (const SiQuantity& q : kQuantities)
        if (si == q.si) return q.words;
    return "a pure number";
}

// The units that convert to `si`, for a message: "rpm, rad/s or deg/s".
std::string units_of(const std::string& si) {
    std::vector<std::string> units;
    for (const UnitFactor& u : kUnits)
        if (si == u.si) units.emplace_back(u.unit);
    std::string text;
    for (std::size_t i = 0; i < units.size(); ++i)
        text += (i == 0 ? "" : i + 1 == units.size() ? " or " : ", ") + units[i];
    return text;
}

// A channel's `unit:` must measure what the model reads from it (`expected`, its SI unit:
// an input's from the element that reads it, an output's from its kind and node): rpm on
// a torque, or mm/s on a rotational node, would be a silent factor. `linear_note` says a
// linear node's motion where the quantity depends on it.
void check_unit_quantity(const YamlMap& section, const std::string& name, const std::string& expected,
                         const std::string& linear_note) {
    const YAML::Node value = section.get(name);
    if (!value.IsMap() || expected.empty()) return;
    const YamlMap m(section.source(), value, section.key_path(name));
    if (!m.has("unit")) return;
    const std::string unit = m.text("unit");
    for (const UnitFactor& u : kUnits)
        if (unit == u.unit && expected != u.si)
            m.fail("unit", "'" + unit + "' is a unit of " + quantity_of(u.si).substr(quantity_of(u.si).find(' ') + 1) +
                               ", and " + name + " is " + quantity_of(expected) + " [" + expected + "]" + linear_note +
                               ": give " + units_of(expected) + ", or scale: for another factor");
}

std::string unit_list() {
    std::string out;
    for (const UnitFactor& u : kUnits) out.append(out.empty() ? "" : ", ").append(u.unit);
    return out;
}

// A column name, or { column: NAME, unit: U | scale: S, ... }. `extra` are further keys
// the mapping may hold (read by the caller).
// A channel's `delay:`: a number, or a parameter declared under `parameters:`. A delay
// moves the data, not the model, so a preset's network takes it on as one more parameter.
Field read_delay(const YamlMap& m, NetworkSpec& network, const std::vector<std::string>& declared) {
    const YAML::Node node = m.get("delay");
    if (node.IsScalar() && network.parameter_index(node.Scalar()) < 0 &&
        std::find(declared.begin(), declared.end(), node.Scalar()) != declared.end())
        network.parameter_names.push_back(node.Scalar());
    const Field delay = read_field(m.source(), node, m.key_path("delay"), network.parameter_names);
    if (delay.is_parameter() && std::find(network.delay_parameters.begin(), network.delay_parameters.end(),
                                          delay.parameter) == network.delay_parameters.end())
        network.delay_parameters.push_back(delay.parameter);
    return delay;
}

ChannelBinding read_binding(const YamlMap& section, const std::string& name, const std::vector<RecordingRead>& recordings,
                            NetworkSpec& network, const std::vector<std::string>& declared,
                            std::initializer_list<std::string_view> extra) {
    const YamlSource& src = section.source();
    const YAML::Node value = section.get(name);
    ChannelBinding b;
    b.model_name = name;
    YAML::Node column_node = value;
    std::string column_path = section.key_path(name);
    if (value.IsMap()) {
        const YamlMap m(src, value, column_path);
        std::vector<std::string> allowed{"column", "unit", "scale", "delay"};
        for (std::string_view e : extra) allowed.emplace_back(e);
        m.allow_only(allowed);
        if (!m.has("column")) m.fail_missing("column", "(the CSV column)");
        column_node.reset(m.get("column"));  // rebind: operator= would overwrite the tree's node
        column_path = m.key_path("column");
        if (m.has("unit") && m.has("scale")) m.fail("scale", "give either unit or scale, not both");
        if (m.has("unit")) {
            const std::string unit = m.text("unit");
            b.scale = unit_to_si(unit);
            if (b.scale == 0.0) m.fail("unit", "unknown unit '" + unit + "' (units: " + unit_list() + ")");
        }
        if (m.has("scale")) {
            b.scale = m.number("scale");
            if (b.scale == 0.0) m.fail("scale", "a scale of 0 removes the channel");
        }
        if (m.has("delay")) {  // a parameter's bounds are checked with the parameters
            b.delay = read_delay(m, network, declared);
            for (const RecordingRead& r : recordings)  // each recording is shifted on its own
                if (!b.delay.is_parameter() && !(std::abs(b.delay.constant) < r.seconds()))
                    m.fail("delay", "a delay of " + number_text(b.delay.constant) + " s shifts the channel past " +
                                        r.phrase() + " (" + number_text(r.seconds()) + " s long)");
        }
    } else if (!value.IsScalar()) {
        src.fail(value, column_path, "expected a CSV column name or { column: NAME, unit: U }");
    }
    b.column = read_text(src, column_node, column_path);
    b.where = src.where(column_node, column_path);
    for (const RecordingRead& r : recordings)  // every recording holds every column read
        if (!r.table.has_column(b.column))
            src.fail(column_node, column_path,
                     "no column '" + b.column + "' in " + r.table.file().string() +
                         " (columns: " + join_words(r.table.column_names()) + ")");
    return b;
}

// "speed: NODE", "torque: ELEMENT": how each output kind is written (model/output_kinds.hpp).
std::vector<std::string> output_forms() {
    std::vector<std::string> forms;
    for_each_output_kind([&](auto kind) {
        using K = decltype(kind);
        forms.push_back(std::string(K::key) + (K::target == outputs::Target::node ? ": NODE" : ": ELEMENT"));
    });
    return forms;
}

// "a, b or c".
std::string either(const std::vector<std::string>& words) {
    std::string text;
    for (std::size_t i = 0; i < words.size(); ++i) text += (i == 0 ? "" : i + 1 == words.size() ? " or " : ", ") + words[i];
    return text;
}

// The element of a torque output, and the side it reads where its kind has two
// (ElementOutputs::torque_each_side: a gear mesh).
void read_output_element(const YamlMap& m, const std::string& key, const NetworkSpec& net, OutputSpec& o) {
    const std::string element = m.text(key);
    if (!net.find_element(element, o.element)) m.fail(key, "no element named '" + element + "'");
    for_each_element_kind([&](auto kind) {
        using K = decltype(kind);
        if (ElementRow<K>::kind == o.element.kind && K::outputs == ElementOutputs::none)
            m.fail(key, std::string("a ") + K::type_name + " offers no torque output (it ties its nodes rigidly; its "
                        "torque is the constraint's): read the torque of a shaft beside it");
    });
    if (!m.has("side")) return;
    o.side = m.choice("side", {"input", "output"}) == "output" ? TorqueSide::output : TorqueSide::input;
    if (element_has_output_side(o.element.kind)) return;
    std::vector<std::string> two_sided;
    for_each_element_kind([&](auto kind) {
        if (decltype(kind)::outputs == ElementOutputs::torque_each_side) two_sided.emplace_back(decltype(kind)::type_name);
    });
    m.fail("side", std::string("a ") + element_kind_name(o.element.kind) +
                       " carries the same torque on both sides; side: applies to a " + either(two_sided));
}

OutputSpec read_custom_output(const YamlMap& section, const std::string& name, const NetworkSpec& net) {
    const YamlSource& src = section.source();
    const YAML::Node value = section.get(name);
    const std::vector<std::string> forms = output_forms();
    if (!value.IsMap()) {
        std::string others;
        for (std::size_t i = 1; i < forms.size(); ++i) others += (i == 1 ? "" : ", ") + forms[i];
        src.fail(value, section.key_path(name), "expected { column: NAME, " + forms[0] + " } (or " + others + ")");
    }
    const YamlMap m(src, value, section.key_path(name));
    OutputSpec o;
    o.name = name;
    int kinds = 0;
    std::string first_key, last_given, element_output;
    for_each_output_kind([&](auto kind) {
        using K = decltype(kind);
        if (first_key.empty()) first_key = K::key;
        if (K::target == outputs::Target::element && element_output.empty())
            element_output = std::string("a ") + K::key + " output (" + K::key + ": ELEMENT)";
        if (!m.has(K::key)) return;
        ++kinds;
        last_given = K::key;
        o.kind = OutputRow<K>::kind;
    });
    if (kinds == 0) m.fail_missing(first_key, "(give exactly one of " + either(forms) + ")");
    if (kinds > 1) m.fail(last_given, "give exactly one of " + either(forms));
    for_each_output_kind([&](auto kind) {
        using K = decltype(kind);
        if (o.kind != OutputRow<K>::kind) return;
        if constexpr (K::target == outputs::Target::element) {
            read_output_element(m, K::key, net, o);
        } else {
            const std::string node = m.text(K::key);
            o.node = net.node_index(node);
            if (o.node < 0) m.fail(K::key, "no node named '" + node + "'");
            if (m.has("side")) m.fail("side", "side: applies to " + element_output);
        }
    });
    if (m.has("offset")) o.offset = read_field(src, m.get("offset"), m.key_path("offset"), net.parameter_names);
    if (m.has("gain")) {
        o.gain = read_field(src, m.get("gain"), m.key_path("gain"), net.parameter_names);
        if (!o.gain.is_parameter() && o.gain.constant == 0.0) m.fail("gain", "a gain of 0 removes the output");
    }
    return o;
}

// Absolute cylinder pressure [Pa]: never below vacuum, at its lowest (intake, exhaust)
// near atmospheric even with boost, at its peak (compression, firing) above atmospheric
// and below what any engine withstands.
constexpr double kLowestPressureAtMost = 5e5;   // 5 bar
constexpr double kPeakPressureAtLeast = 0.8e5;  // 0.8 bar
constexpr double kPeakPressureAtMost = 5e7;     // 500 bar

bool plausible_cylinder_pressure(double lowest, double peak) {
    return lowest >= 0 && lowest <= kLowestPressureAtMost && peak >= kPeakPressureAtLeast && peak <= kPeakPressureAtMost;
}

}  // namespace

// One recording's cylinder pressure channel (check_cylinder_pressures).
static void check_cylinder_pressure(const YamlMap& inputs, const ChannelBinding& in, const RecordingRead& r) {
    const std::vector<double>& p = r.table.column(in.column);
    const auto [lo, hi] = std::minmax_element(p.begin(), p.end());
    if (plausible_cylinder_pressure(*lo * in.scale, *hi * in.scale)) return;
    std::string fits;
    for (const char* unit : {"Pa", "kPa", "bar", "MPa"})
        if (plausible_cylinder_pressure(*lo * unit_to_si(unit), *hi * unit_to_si(unit)))
            fits.append(fits.empty() ? "" : " or ").append(unit);
    const std::string hint = fits.empty() ? "; check the column, or set its unit (Pa, kPa, bar or MPa)"
                                          : "; the numbers fit " + fits + ": set unit: " + fits.substr(0, fits.find(' '));
    const std::string of = r.recording.name.empty() ? "" : " of " + r.phrase();
    inputs.fail(in.model_name,
                "column '" + in.column + "'" + of + " reads " + number_text(*lo * in.scale) + " … " +
                    number_text(*hi * in.scale) + " Pa" +
                    (in.scale == 1.0 ? "" : " (values × " + number_text(in.scale) + ")") +
                    ": not an absolute cylinder pressure (expected a lowest value of 0 … 5 bar and a peak of "
                    "0.8 … 500 bar)" + hint);
}

void check_cylinder_pressures(const YamlMap& inputs, const std::vector<ChannelBinding>& bindings,
                              const std::vector<RecordingRead>& recordings) {
    for (const ChannelBinding& in : bindings)
        if (in.by_angle)
            for (const RecordingRead& r : recordings) check_cylinder_pressure(inputs, in, r);
}

double unit_to_si(const std::string& unit) {
    for (const UnitFactor& u : kUnits)
        if (unit == u.unit) return u.factor;
    return 0.0;
}

// An input's `noise:`: the standard deviation of the white noise it was logged with, in the
// channel's unit (before unit: or scale:), > 0; stored in SI.
static void read_input_noise(const YamlMap& inputs, const std::string& name, ChannelBinding& b) {
    const YAML::Node value = inputs.get(name);
    if (!value.IsMap()) return;
    const YamlMap m(inputs.source(), value, inputs.key_path(name));
    if (!m.has("noise")) return;
    const double noise = m.number("noise");
    if (!(noise > 0.0) || !std::isfinite(noise))
        m.fail("noise", "the standard deviation of the input's noise must be a positive number (in the column's unit); "
                        "leave it out for an input logged without noise");
    if (b.by_angle)
        m.fail("noise", "a cylinder pressure is read by crank angle, and its noise is not propagated: declare "
                        "noise on a torque or speed input");
    b.noise = noise * std::abs(b.scale);
}

std::vector<ChannelBinding> read_inputs(const YamlMap& inputs, NetworkSpec& network,
                                        const std::vector<RecordingRead>& recordings,
                                        const std::vector<std::string>& declared) {
    std::vector<std::string> names = network.input_names;
    names.insert(names.end(), network.angle_input_names.begin(), network.angle_input_names.end());
    inputs.allow_only(names);
    std::vector<ChannelBinding> out;
    for (std::size_t i = 0; i < names.size(); ++i) {
        const std::string& name = names[i];
        if (!inputs.has(name)) inputs.fail_missing(name, "(the CSV column of model input " + name + ")");
        out.push_back(read_binding(inputs, name, recordings, network, declared, {"noise"}));
        out.back().by_angle = i >= network.input_names.size();
        read_input_noise(inputs, name, out.back());
        if (out.back().by_angle) {
            check_unit_quantity(inputs, name, "Pa", "");
        } else {
            const int node = input_node(network, i);
            const bool linear = node >= 0 && network.nodes[static_cast<std::size_t>(node)].linear;
            check_unit_quantity(inputs, name, input_unit(network, i),
                                node < 0  ? ""
                                : linear ? " (read on a node with motion: linear)"
                                         : " (read on a rotational node)");
        }
        if (out.back().by_angle && out.back().delay.is_parameter())
            YamlMap(inputs.source(), inputs.get(name), inputs.key_path(name))
                .fail("delay", "a cylinder pressure is read by crank angle: its delay must be a number");
    }
    return out;
}

// A measured output so large that a squared residual overflows the cost would make every
// candidate fail and be blamed on the simulation: refused with the cell.
static void check_output_magnitude(const ChannelBinding& b, const CsvTable& data) {
    constexpr double kMaxMeasuredOutput = 1e100;
    const std::vector<double>& v = data.column(b.column);
    for (std::size_t i = 0; i < v.size(); ++i)
        if (std::abs(v[i] * b.scale) > kMaxMeasuredOutput)
            throw InputError(data.file().string(), data.line_of_row(i), "column " + b.column,
                             "the measured output " + b.model_name + " is " + number_text(v[i] * b.scale) +
                                 ", beyond the 1e100 at which a squared residual overflows the cost: check the "
                                 "column and its unit");
}

OutputBindings read_outputs(const YamlMap& outputs, NetworkSpec& network, const std::vector<RecordingRead>& recordings,
                            const std::vector<std::string>& declared) {
    const bool custom = network.preset == "custom";
    OutputBindings out;
    if (!custom) {
        std::vector<std::string> names;
        for (const OutputSpec& o : network.outputs) names.push_back(o.name);
        outputs.allow_only(names);
    }
    for (const std::string& name : outputs.keys()) {
        if (const std::string why = plain_name_problem(name); !why.empty()) outputs.fail(name, why);
        if (const YAML::Node v = outputs.get(name); v.IsMap() && YamlMap(outputs.source(), v, outputs.key_path(name)).has("noise"))
            YamlMap(outputs.source(), v, outputs.key_path(name))
                .fail("noise", "noise: is declared on an input (the noise the simulation reads and the line never felt); "
                               "an output's measurement noise is taken from its residual");
        if (custom) {
            if (network.output_index(name) >= 0) outputs.fail(name, "output defined twice");
            network.outputs.push_back(read_custom_output(outputs, name, network));
            out.channels.push_back(
                read_binding(outputs, name, recordings, network, declared,
                             {"speed", "angle", "torque", "side", "offset", "gain", "weight", "detrend", "highpass"}));
        } else {
            out.channels.push_back(
                read_binding(outputs, name, recordings, network, declared, {"weight", "detrend", "highpass"}));
        }
        if (const YAML::Node v = outputs.get(name); v.IsMap()) {
            const YamlMap m(outputs.source(), v, outputs.key_path(name));
            if (m.has("weight")) {
                const double w = m.number("weight");
                if (!(w > 0) || !std::isfinite(w)) m.fail("weight", "an output's weight must be a positive number");
                // Relative factors: beyond 1e8 one output's squared residual swamps the
                // others past double precision, and a weight of 1e154 overflows the cost.
                if (w < kSmallestWeight || w > kLargestWeight)
                    m.fail("weight", "an output's weight must be between 1e-08 and 1e+08 (weights are relative; got " +
                                         number_text(w) + ")");
                out.channels.back().weight = w;
            }
            ScoringFilter& f = out.channels.back().scoring;
            if (m.has("detrend"))
                f.detrend = m.choice("detrend", {"mean", "linear"}) == "mean" ? Detrend::mean : Detrend::linear;
            if (m.has("highpass")) {
                f.highpass = m.number("highpass");
                for (const RecordingRead& r : recordings) {
                    const double nyquist = 0.5 * static_cast<double>(r.table.rows() - 1) / r.seconds();
                    if (!(f.highpass > 0) || !(f.highpass < nyquist))
                        m.fail("highpass", "a high-pass cut-off is a frequency in Hz between 0 and " + r.phrase() +
                                               "'s Nyquist frequency, " + number_text(nyquist) + " Hz");
                }
            }
        }
        out.indices.push_back(network.output_index(name));
        if (out.indices.back() >= 0) {
            const OutputSpec& o = network.outputs[static_cast<std::size_t>(out.indices.back())];
            const bool on_node = output_reads_node(o.kind);
            const NodeSpec* node =
                on_node && o.node >= 0 && static_cast<std::size_t>(o.node) < network.nodes.size()
                    ? &network.nodes[static_cast<std::size_t>(o.node)]
                    : nullptr;
            check_unit_quantity(outputs, name, output_unit(network, o),
                                node ? (node->linear ? " (node " + node->name + " has motion: linear)"
                                                     : " (node " + node->name + " turns: rotational)")
                                     : std::string());
        }
        for (const RecordingRead& r : recordings) check_output_magnitude(out.channels.back(), r.table);
    }
    if (out.channels.empty())
        outputs.source().fail(outputs.node(), outputs.path(), "no outputs: name at least one model output and its CSV column");
    return out;
}

}  // namespace tvid

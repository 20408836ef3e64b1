#include "tvid/experiment/model_reader.hpp"

#include "tvid/io/atomic_file.hpp"
#include "tvid/util/text.hpp"

#include <algorithm>
#include <set>

#include "tvid/experiment/yaml_element_source.hpp"
#include "tvid/model/element_reading.hpp"
#include "tvid/model/elements/composite_kinds.hpp"
#include "tvid/model/presets.hpp"
#include "tvid/model/rigid_gears.hpp"

namespace tvid {

namespace {

NetworkSpec read_preset(const YamlMap& model, PresetConstants& constants) {
    const std::string name = model.text("preset");
    const PresetInfo* info = find_preset(name);
    if (info == nullptr) {
        std::vector<std::string> names;
        for (const PresetInfo& p : preset_catalogue()) names.push_back(p.name);
        model.fail("preset", "unknown preset '" + name + "' (presets: " + join_words(names) + ")");
    }
    std::vector<std::string> allowed{"preset"};
    allowed.insert(allowed.end(), info->constants.begin(), info->constants.end());
    model.allow_only(allowed);
    for (const std::string& c : info->constants) {
        if (!model.has(c)) continue;
        const YAML::Node value = model.get(c);
        std::vector<double>& numbers = constants[c];
        if (value.IsSequence()) {
            for (std::size_t i = 0; i < value.size(); ++i) numbers.push_back(read_number(model.source(), value[i], model.key_path(c)));
        } else {
            numbers.push_back(model.number(c));
        }
    }
    try {
        return build_preset(name, constants);
    } catch (const PresetConstantError& e) {
        model.fail(e.constant(), e.what());
    }
}

// Reads a custom network. Node and element names are unique; "ground" is the fixed base.
// Each element's `type:` names a kind of the element table or of the composite table,
// whose own file reads it (model/elements/NAME.hpp).
class NetworkReader {
public:
    NetworkReader(const YamlMap& model, const std::vector<std::string>& parameters)
        : model_(model), src_(model.source()) {
        net_.preset = "custom";
        net_.parameter_names = parameters;
    }

    NetworkSpec read() {
        model_.allow_only({"nodes", "elements"});
        read_nodes();
        read_elements();
        return net_;
    }

private:
    Field field(const YamlMap& m, const std::string& key) const {
        if (!m.has(key)) m.fail_missing(key);
        return read_field(src_, m.get(key), m.key_path(key), net_.parameter_names);
    }

    void read_nodes() {
        if (!model_.has("nodes")) model_.fail_missing("nodes", "(a list of { name, J } or { name, inverse_J }, optionally motion: linear)");
        const YAML::Node list = model_.get("nodes");
        const std::string path = model_.key_path("nodes");
        if (!list.IsSequence() || list.size() == 0) src_.fail(list, path, "expected a non-empty list of nodes");
        for (std::size_t i = 0; i < list.size(); ++i) {
            const YamlMap m(src_, list[i], path + "[" + std::to_string(i) + "]");
            m.allow_only({"name", "J", "inverse_J", "motion"});
            NodeSpec n;
            n.name = m.text("name");
            if (n.name == "ground") m.fail("name", "'ground' is the fixed base; give the node another name");
            if (const std::string why = plain_name_problem(n.name); !why.empty()) m.fail("name", why);
            if (net_.node_index(n.name) >= 0) m.fail("name", "a node named '" + n.name + "' already exists");
            if (m.has("J") && m.has("inverse_J")) m.fail("inverse_J", "give either J or inverse_J, not both");
            if (!m.has("J") && !m.has("inverse_J")) m.fail_missing("J", "(give exactly one of J or inverse_J)");
            n.inverse = m.has("inverse_J");
            n.inertia = field(m, n.inverse ? "inverse_J" : "J");
            if (!n.inertia.is_parameter() && !(n.inertia.constant > 0))
                m.fail(n.inverse ? "inverse_J" : "J", "an inertia must be positive");
            if (m.has("motion")) n.linear = m.choice("motion", {"rotational", "linear"}) == "linear";
            net_.nodes.push_back(n);
        }
    }

    // Every type name of the experiment file: the element kinds, then the composites.
    static std::vector<std::string> type_names() {
        std::vector<std::string> names;
        for_each_element_kind([&](auto kind) { names.emplace_back(decltype(kind)::type_name); });
        for_each_composite_kind([&](auto kind) { names.emplace_back(decltype(kind)::type_name); });
        return names;
    }

    // "torque, cylinder or speed_source": the kinds that read a measured channel.
    static std::string channel_readers() {
        std::vector<std::string> names;
        for_each_element_kind([&](auto kind) {
            if (decltype(kind)::channel.unit != nullptr) names.emplace_back(decltype(kind)::type_name);
        });
        std::string text;
        for (std::size_t i = 0; i < names.size(); ++i)
            text += (i == 0 ? "" : i + 1 == names.size() ? " or " : ", ") + names[i];
        return text;
    }

    // The element `name` of kind `type`, from the entry m, by the kind's own reader.
    void read_element_of_type(const YamlMap& m, const std::string& type, const std::string& name) {
        YamlElementSource source(m, net_, names_);
        for_each_element_kind([&](auto kind) {
            using K = decltype(kind);
            if (type != K::type_name) return;
            m.allow_only(element_keys<K>());
            read_element<K>(source, name, net_);
        });
        for_each_composite_kind([&](auto kind) {
            using K = decltype(kind);
            if (type != K::type_name) return;
            m.allow_only(element_keys<K>());
            K::build(source, name, net_);
        });
    }

    void read_elements() {
        if (!model_.has("elements")) model_.fail_missing("elements", "(a list of elements with a type)");
        const YAML::Node list = model_.get("elements");
        const std::string path = model_.key_path("elements");
        if (!list.IsSequence()) src_.fail(list, path, "expected a list of elements");
        const std::vector<std::string> types = type_names();
        for (std::size_t i = 0; i < list.size(); ++i) {
            const YamlMap m(src_, list[i], path + "[" + std::to_string(i) + "]");
            const std::string type = m.choice("type", types);
            const std::string name = m.has("name") ? m.text("name") : type + std::to_string(i + 1);
            if (!names_.insert(name).second) m.fail("name", "an element named '" + name + "' already exists");
            if (const std::string why = plain_name_problem(name); !why.empty()) m.fail("name", why);
            read_element_of_type(m, type, name);
        }
        check_rigid_gears(list, path);
        if (net_.input_names.empty() && net_.angle_input_names.empty())
            src_.fail(list, path,
                      "no element of type " + channel_readers() + " reads a channel: no measurement drives the network");
        finish_reading(net_);
    }

    // Ideal gears that cannot be reduced (rigid_gears.hpp): refused at the element named.
    void check_rigid_gears(const YAML::Node& list, const std::string& path) const {
        std::string culprit;
        const std::string why = rigid_gear_problem(net_, &culprit);
        if (why.empty()) return;
        for (std::size_t i = 0; i < list.size(); ++i) {
            const YamlMap m(src_, list[i], path + "[" + std::to_string(i) + "]");
            const std::string type = m.text("type");
            if ((m.has("name") ? m.text("name") : type + std::to_string(i + 1)) == culprit)
                m.fail(m.has("between") ? "between" : "node", why);
        }
        src_.fail(list, path, why);
    }

    const YamlMap& model_;
    const YamlSource& src_;
    NetworkSpec net_;
    std::set<std::string> names_;  ///< the element names taken
};

void mark(const Field& f, std::vector<bool>& used) {
    if (f.is_parameter()) used[static_cast<std::size_t>(f.parameter)] = true;
}

}  // namespace

Field read_field(const YamlSource& src, const YAML::Node& node, const std::string& path,
                 const std::vector<std::string>& parameter_names) {
    if (!node.IsScalar()) src.fail(node, path, "expected a number or a parameter name");
    const std::string& s = node.Scalar();
    const auto it = std::find(parameter_names.begin(), parameter_names.end(), s);
    if (it != parameter_names.end()) return Field::param(static_cast<int>(it - parameter_names.begin()));
    const char c = s.empty() ? ' ' : s.front();
    if ((c >= '0' && c <= '9') || c == '-' || c == '+' || c == '.') return Field::value(read_number(src, node, path));
    src.fail(node, path, "'" + s + "' is neither a number nor a parameter declared under parameters");
}

NetworkSpec read_model(const YamlMap& model, const std::vector<std::string>& declared_parameters,
                       PresetConstants& constants) {
    if (model.has("preset")) return read_preset(model, constants);
    if (!model.has("nodes") && !model.has("elements"))
        model.fail_missing("preset", "(give preset: NAME, or nodes: and elements: for a custom network)");
    return NetworkReader(model, declared_parameters).read();
}

std::vector<bool> parameters_in_use(const NetworkSpec& n) {
    std::vector<bool> used(n.parameter_names.size(), false);
    for (const auto& e : n.nodes) mark(e.inertia, used);
    for_each_element_field(n, [&](const FieldInfo&, const Field& f) { mark(f, used); });
    for (int p : n.delay_parameters) mark(Field::param(p), used);
    for (const auto& o : n.outputs) {
        mark(o.offset, used);
        mark(o.gain, used);
    }
    return used;
}

}  // namespace tvid

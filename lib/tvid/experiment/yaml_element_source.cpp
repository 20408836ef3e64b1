#include "tvid/experiment/yaml_element_source.hpp"

#include <algorithm>
#include <cctype>
#include <vector>

#include "tvid/experiment/model_reader.hpp"
#include "tvid/util/text.hpp"

namespace tvid {

Field YamlElementSource::field(const std::string& key) const {
    if (!m_.has(key)) m_.fail_missing(key);
    return read_field(src_, m_.get(key), m_.key_path(key), net_.parameter_names);
}

bool YamlElementSource::names_constant(const std::string& key) const {
    const YAML::Node given = m_.get(key);
    const std::string text = given.IsScalar() ? given.Scalar() : std::string();
    return !text.empty() && (std::isdigit(static_cast<unsigned char>(text.front())) || text.front() == '-' ||
                             text.front() == '+' || text.front() == '.' || net_.parameter_index(text) >= 0);
}

int YamlElementSource::node(const std::string& key) const {
    if (!m_.has(key)) m_.fail_missing(key);
    const YAML::Node value = m_.get(key);
    const std::string path = m_.key_path(key);
    const std::string name = read_text(src_, value, path);
    if (name == "ground") src_.fail(value, path, "'ground' is not allowed here (it has no inertia)");
    const int i = net_.node_index(name);
    if (i < 0) src_.fail(value, path, "no node named '" + name + "' (nodes: " + node_names() + ")");
    return i;
}

// A node named in `between`.
int YamlElementSource::node_at(const YAML::Node& value, bool ground_ok) const {
    const std::string path = m_.key_path("between");
    const std::string name = read_text(src_, value, path);
    if (name == "ground") {
        if (!ground_ok) src_.fail(value, path, "'ground' is not allowed here (it has no inertia)");
        return kGround;
    }
    const int i = net_.node_index(name);
    if (i < 0) src_.fail(value, path, "no node named '" + name + "' (nodes: " + node_names() + ")");
    return i;
}

// `between: [a, b]`, `[a]` or `[a, ground]`; two-node elements need `ground_ok` false.
std::pair<int, int> YamlElementSource::between(bool ground_ok) const {
    if (!m_.has("between")) m_.fail_missing("between", "(between: [node_a, node_b])");
    const YAML::Node b = m_.get("between");
    const std::string path = m_.key_path("between");
    if (!b.IsSequence() || b.size() < 1 || b.size() > 2)
        src_.fail(b, path, "expected [node_a, node_b]" + std::string(ground_ok ? " or [node] (to ground)" : ""));
    if (b.size() == 1 && !ground_ok) src_.fail(b, path, "expected two nodes [node_a, node_b]");
    const int a = node_at(b[0], false);
    const int c = b.size() == 2 ? node_at(b[1], ground_ok) : kGround;
    if (a == c) src_.fail(b, path, "an element cannot join a node to itself");
    return {a, c};
}

std::vector<std::unique_ptr<ElementSource>> YamlElementSource::entries(const std::string& key,
                                                                       const std::vector<std::string>& allowed) const {
    if (!m_.has(key)) m_.fail_missing(key);
    const YAML::Node list = m_.get(key);
    const std::string path = m_.key_path(key);
    if (!list.IsSequence() || list.size() == 0)
        src_.fail(list, path, "expected a list of mappings [{" + join_words(allowed) + "}, ...]");
    std::vector<std::unique_ptr<ElementSource>> out;
    for (std::size_t i = 0; i < list.size(); ++i) {
        YamlMap entry(src_, list[i], path + "[" + std::to_string(i) + "]");
        entry.allow_only(allowed);
        out.push_back(std::make_unique<YamlElementSource>(std::move(entry), net_, names_));
    }
    return out;
}

std::pair<Field, Field> YamlElementSource::field_pair(const std::string& key) const {
    if (!m_.has(key)) m_.fail_missing(key);
    const YAML::Node pair = m_.get(key);
    const std::string path = m_.key_path(key);
    if (!pair.IsSequence() || pair.size() != 2) src_.fail(pair, path, "expected [min, max]");
    return {read_field(src_, pair[0], path + "[0]", net_.parameter_names),
            read_field(src_, pair[1], path + "[1]", net_.parameter_names)};
}

std::string YamlElementSource::node_name(int node) const {
    return node == kGround ? std::string("ground") : net_.nodes[static_cast<std::size_t>(node)].name;
}

std::string YamlElementSource::node_names() const {
    std::vector<std::string> n;
    for (const NodeSpec& s : net_.nodes) n.push_back(s.name);
    return join_words(n);
}

// The index of the input by time named at `key` (added to the model's inputs when new).
int YamlElementSource::time_input(const std::string& key, const char* what) {
    const std::string input = m_.text(key);
    if (std::find(net_.angle_input_names.begin(), net_.angle_input_names.end(), input) != net_.angle_input_names.end())
        m_.fail(key, "'" + input + "' is a cylinder pressure read by crank angle, not " + what + " by time");
    int k = net_.input_index(input);
    if (k < 0) {
        net_.input_names.push_back(input);
        k = static_cast<int>(net_.input_names.size() - 1);
    }
    return k;
}

// The index of the input by crank angle named at `key` (added when new).
int YamlElementSource::angle_input(const std::string& key) {
    const std::string pressure = m_.text(key);
    if (net_.input_index(pressure) >= 0)
        m_.fail(key, "'" + pressure + "' already drives a torque by time; a pressure is read by crank angle");
    auto it = std::find(net_.angle_input_names.begin(), net_.angle_input_names.end(), pressure);
    if (it == net_.angle_input_names.end()) {
        net_.angle_input_names.push_back(pressure);
        it = net_.angle_input_names.end() - 1;
    }
    return static_cast<int>(it - net_.angle_input_names.begin());
}

}  // namespace tvid

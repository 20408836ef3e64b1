#include "tvid/experiment/model_reader.hpp"

#include "tvid/io/atomic_file.hpp"
#include "tvid/util/text.hpp"

#include <algorithm>
#include <cctype>
#include <set>

#include "tvid/model/presets.hpp"

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
    Field field_or(const YamlMap& m, const std::string& key, const Field& fallback) const {
        return m.has(key) ? field(m, key) : fallback;
    }

    // A constant field must keep the sign its element's field table asks for (a parameter
    // is checked in parameter_reader). A clearance law's k_minus/k_plus and c_minus/c_plus
    // may have come from the shorthand k and c: the error points at the key that was given.
    template <class Kind>
    void check_signs(const YamlMap& m, const typename Kind::Spec& e) const {
        Kind::for_each_field(
            [&](const FieldInfo& info, const Field& f) {
                if (!info.in_use || f.is_parameter() || !violates_sign(info.sign, f.constant)) return;
                const std::string name = info.name;
                std::string key = name;
                if (!m.has(key) && (name == "k_minus" || name == "k_plus")) key = "k";
                if (!m.has(key) && (name == "c_minus" || name == "c_plus")) key = "c";
                m.fail(key, std::string(info.sign == SignRule::positive ? "must be positive: " : "cannot be negative: ") +
                                info.role + " (got " + number_text(f.constant) + ")");
            },
            e);
    }

    int node(const YamlMap& m, const std::string& key, const YAML::Node& value, bool ground_ok) const {
        const std::string path = m.key_path(key);
        const std::string name = read_text(src_, value, path);
        if (name == "ground") {
            if (!ground_ok) src_.fail(value, path, "'ground' is not allowed here (it has no inertia)");
            return kGround;
        }
        const int i = net_.node_index(name);
        if (i < 0) src_.fail(value, path, "no node named '" + name + "' (nodes: " + node_names() + ")");
        return i;
    }

    std::string node_names() const {
        std::vector<std::string> n;
        for (const NodeSpec& s : net_.nodes) n.push_back(s.name);
        return join_words(n);
    }

    // `between: [a, b]`, `[a]` or `[a, ground]`; two-node elements need `ground_ok` false.
    std::pair<int, int> between(const YamlMap& m, bool ground_ok) const {
        if (!m.has("between")) m.fail_missing("between", "(between: [node_a, node_b])");
        const YAML::Node b = m.get("between");
        const std::string path = m.key_path("between");
        if (!b.IsSequence() || b.size() < 1 || b.size() > 2)
            src_.fail(b, path, "expected [node_a, node_b]" + std::string(ground_ok ? " or [node] (to ground)" : ""));
        if (b.size() == 1 && !ground_ok) src_.fail(b, path, "expected two nodes [node_a, node_b]");
        const int a = node(m, "between", b[0], false);
        const int c = b.size() == 2 ? node(m, "between", b[1], ground_ok) : kGround;
        if (a == c) src_.fail(b, path, "an element cannot join a node to itself");
        return {a, c};
    }

    void read_nodes() {
        if (!model_.has("nodes")) model_.fail_missing("nodes", "(a list of { name, J } or { name, inverse_J })");
        const YAML::Node list = model_.get("nodes");
        const std::string path = model_.key_path("nodes");
        if (!list.IsSequence() || list.size() == 0) src_.fail(list, path, "expected a non-empty list of nodes");
        for (std::size_t i = 0; i < list.size(); ++i) {
            const YamlMap m(src_, list[i], path + "[" + std::to_string(i) + "]");
            m.allow_only({"name", "J", "inverse_J"});
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
            net_.nodes.push_back(n);
        }
    }

    void read_clearance_fields(const YamlMap& m, Field& k_minus, Field& k_plus, Field& c_minus, Field& c_plus,
                               Field& mu, Field& sigma, bool& smooth, const Field* k, const Field* c) const {
        auto stiffness = [&](const char* key) {
            if (!m.has(key) && k == nullptr) m.fail_missing(key);
            return m.has(key) ? field(m, key) : *k;
        };
        auto damping = [&](const char* key) {
            if (!m.has(key) && c == nullptr) m.fail_missing(key);
            return m.has(key) ? field(m, key) : *c;
        };
        k_minus = stiffness("k_minus");
        k_plus = stiffness("k_plus");
        c_minus = damping("c_minus");
        c_plus = damping("c_plus");
        mu = field(m, "mu");
        smooth = m.has("sigma");
        if (smooth) sigma = field(m, "sigma");
    }

    void read_elements() {
        if (!model_.has("elements")) model_.fail_missing("elements", "(a list of elements with a type)");
        const YAML::Node list = model_.get("elements");
        const std::string path = model_.key_path("elements");
        if (!list.IsSequence()) src_.fail(list, path, "expected a list of elements");
        std::set<std::string> names;
        for (std::size_t i = 0; i < list.size(); ++i) {
            const YamlMap m(src_, list[i], path + "[" + std::to_string(i) + "]");
            const std::string type =
                m.choice("type", {"spring_damper", "clearance", "friction", "gear_mesh", "torque", "cylinder",
                                  "order_torque", "speed_source", "speed_controller"});
            const std::string name = m.has("name") ? m.text("name") : type + std::to_string(i + 1);
            if (!names.insert(name).second) m.fail("name", "an element named '" + name + "' already exists");
            if (const std::string why = plain_name_problem(name); !why.empty()) m.fail("name", why);
            if (type == "spring_damper") {
                m.allow_only({"type", "name", "between", "k", "c"});
                const auto [a, b] = between(m, true);
                const SpringDamperSpec e{name, a, b, field(m, "k"), field_or(m, "c", Field::value(0.0))};
                check_signs<elements::SpringDamper>(m, e);
                net_.spring_dampers.push_back(e);
            } else if (type == "clearance") {
                m.allow_only({"type", "name", "between", "k", "c", "k_minus", "k_plus", "c_minus", "c_plus", "mu", "sigma"});
                ClearanceSpec e;
                e.name = name;
                std::tie(e.a, e.b) = between(m, true);
                const Field k = field_or(m, "k", Field{}), c = field_or(m, "c", Field::value(0.0));
                read_clearance_fields(m, e.k_minus, e.k_plus, e.c_minus, e.c_plus, e.mu, e.sigma, e.smooth,
                                      m.has("k") ? &k : nullptr, &c);
                check_signs<elements::Clearance>(m, e);
                net_.clearances.push_back(e);
            } else if (type == "friction") {
                m.allow_only({"type", "name", "node", "c"});
                if (!m.has("node")) m.fail_missing("node");
                const FrictionSpec e{name, node(m, "node", m.get("node"), false), field(m, "c")};
                check_signs<elements::Friction>(m, e);
                net_.frictions.push_back(e);
            } else if (type == "gear_mesh") {
                m.allow_only({"type", "name", "between", "ratio", "k", "c", "k_minus", "k_plus", "c_minus", "c_plus",
                              "mu", "sigma"});
                GearMeshSpec e;
                e.name = name;
                std::tie(e.a, e.b) = between(m, false);
                e.ratio = field(m, "ratio");
                e.has_clearance = m.has("mu");
                e.c = field_or(m, "c", Field::value(0.0));
                if (!e.has_clearance) {
                    for (const char* key : {"k_minus", "k_plus", "c_minus", "c_plus", "sigma"})
                        if (m.has(key)) m.fail(key, "clearance fields need mu (the half backlash)");
                    e.k = field(m, "k");
                } else {
                    e.k = field_or(m, "k", Field{});
                    read_clearance_fields(m, e.k_minus, e.k_plus, e.c_minus, e.c_plus, e.mu, e.sigma, e.smooth,
                                          m.has("k") ? &e.k : nullptr, &e.c);
                }
                check_signs<elements::GearMesh>(m, e);
                net_.gear_meshes.push_back(e);
            } else if (type == "cylinder") {
                m.allow_only({"type", "name", "node", "pressure", "phase_deg", "bore", "crank_radius", "rod_length",
                              "mass", "p_atm"});
                if (!m.has("node")) m.fail_missing("node");
                CylinderSpec e;
                e.name = name;
                e.node = node(m, "node", m.get("node"), false);
                const std::string pressure = m.text("pressure");
                if (net_.input_index(pressure) >= 0)
                    m.fail("pressure", "'" + pressure + "' already drives a torque by time; a pressure is read by crank angle");
                auto it = std::find(net_.angle_input_names.begin(), net_.angle_input_names.end(), pressure);
                if (it == net_.angle_input_names.end()) {
                    net_.angle_input_names.push_back(pressure);
                    it = net_.angle_input_names.end() - 1;
                }
                e.pressure = static_cast<int>(it - net_.angle_input_names.begin());
                e.phase = m.has("phase_deg") ? m.number("phase_deg") * 3.14159265358979323846 / 180.0 : 0.0;
                e.bore = field(m, "bore");
                e.crank_radius = field(m, "crank_radius");
                e.rod_length = field(m, "rod_length");
                e.mass = field_or(m, "mass", Field::value(0.0));
                e.p_atm = field_or(m, "p_atm", Field::value(101325.0));
                check_signs<elements::Cylinder>(m, e);
                if (!e.crank_radius.is_parameter() && !e.rod_length.is_parameter() &&
                    !(e.rod_length.constant > e.crank_radius.constant))
                    m.fail("rod_length", "the connecting rod must be longer than the crank radius");
                net_.cylinders.push_back(e);
            } else if (type == "order_torque") {
                m.allow_only({"type", "name", "node", "order", "amplitude", "phase"});
                if (!m.has("node")) m.fail_missing("node");
                OrderTorqueSpec e;
                e.name = name;
                e.node = node(m, "node", m.get("node"), false);
                e.order = m.number("order");
                if (!(e.order > 0) || e.order > 1000)
                    m.fail("order", "an order is a positive number of cycles per revolution of the node (at most 1000)");
                e.amplitude = field(m, "amplitude");
                e.phase = field_or(m, "phase", Field::value(0.0));
                check_signs<elements::OrderTorque>(m, e);
                net_.order_torques.push_back(e);
            } else if (type == "speed_source") {
                m.allow_only({"type", "name", "node", "input", "speed", "scale"});
                read_speed_source(m, name);
            } else if (type == "speed_controller") {
                m.allow_only({"type", "name", "node", "setpoint", "kp", "ki"});
                read_speed_controller(m, name, names);
            } else {  // torque
                m.allow_only({"type", "name", "node", "input", "offset", "scale"});
                if (!m.has("node")) m.fail_missing("node");
                TorqueSpec e;
                e.name = name;
                e.node = node(m, "node", m.get("node"), false);
                e.input = time_input(m, "input", "a torque");
                e.offset = field_or(m, "offset", Field::value(0.0));
                e.scale = field_or(m, "scale", Field::value(1.0));
                check_signs<elements::Torque>(m, e);
                net_.torques.push_back(e);
            }
        }
        if (net_.input_names.empty() && net_.angle_input_names.empty())
            src_.fail(list, path,
                      "no element of type torque, cylinder or speed_source reads a channel: no measurement drives "
                      "the network");
        // A speed channel's slope follows the inputs (speed sources read it as their acceleration).
        for (SpeedSourceSpec& e : net_.speed_sources) {
            if (e.input < 0) continue;
            auto it = std::find(net_.input_rates.begin(), net_.input_rates.end(), e.input);
            if (it == net_.input_rates.end()) it = net_.input_rates.insert(it, e.input);
            e.rate = static_cast<int>(net_.input_names.size()) + static_cast<int>(it - net_.input_rates.begin());
        }
    }

    // The index of the input by time named at `key` (added to the model's inputs when new).
    int time_input(const YamlMap& m, const std::string& key, const char* what) {
        const std::string input = m.text(key);
        if (std::find(net_.angle_input_names.begin(), net_.angle_input_names.end(), input) !=
            net_.angle_input_names.end())
            m.fail(key, "'" + input + "' is a cylinder pressure read by crank angle, not " + what + " by time");
        int k = net_.input_index(input);
        if (k < 0) {
            net_.input_names.push_back(input);
            k = static_cast<int>(net_.input_names.size() - 1);
        }
        return k;
    }

    // A node turning at a measured speed (`input`, times `scale`) or a constant `speed`.
    void read_speed_source(const YamlMap& m, const std::string& name) {
        if (!m.has("node")) m.fail_missing("node");
        SpeedSourceSpec e;
        e.name = name;
        e.node = node(m, "node", m.get("node"), false);
        if (m.has("input") == m.has("speed"))
            m.fail(m.has("input") ? "speed" : "input",
                   "give either input (a measured speed channel) or speed (a constant, rad/s), not both");
        if (m.has("input")) {
            e.input = time_input(m, "input", "a speed");
            e.scale = field_or(m, "scale", Field::value(1.0));
        } else {
            if (m.has("scale")) m.fail("scale", "scale applies to a speed channel (input), not a constant speed");
            e.speed = field(m, "speed");
        }
        add_speed_source(m, e);
    }

    void add_speed_source(const YamlMap& m, const SpeedSourceSpec& e) {
        for (const SpeedSourceSpec& other : net_.speed_sources)
            if (other.node == e.node)
                m.fail("node", "node '" + net_.nodes[static_cast<std::size_t>(e.node)].name + "' already has its speed "
                               "prescribed by '" + other.name + "'");
        net_.speed_sources.push_back(e);
    }

    // A PI speed controller: T = kp·(ω_set − ω) + ki·∫(ω_set − ω) dt on `node`. Its
    // integral is the twist of a spring (k = ki, c = kp) from a reference node that turns
    // at the setpoint: the node NAME.reference, driven by the speed source NAME.setpoint,
    // joined to `node` by the spring-damper NAME, whose torque is the controller's.
    void read_speed_controller(const YamlMap& m, const std::string& name, std::set<std::string>& names) {
        if (!m.has("node")) m.fail_missing("node");
        const int drive = node(m, "node", m.get("node"), false);
        NodeSpec reference;
        reference.name = name + ".reference";
        reference.inertia = Field::value(1.0);  // prescribed motion: its inertia only scales its reaction
        if (net_.node_index(reference.name) >= 0) m.fail("name", "a node named '" + reference.name + "' already exists");
        for (const char* key : {"kp", "ki"}) {
            const Field f = field(m, key);
            if (!f.is_parameter() && !(f.constant >= 0))
                m.fail(key, "cannot be negative: a controller gain (got " + number_text(f.constant) + ")");
        }
        SpeedSourceSpec setpoint;
        setpoint.name = name + ".setpoint";
        if (!names.insert(setpoint.name).second) m.fail("name", "an element named '" + setpoint.name + "' already exists");
        setpoint.node = static_cast<int>(net_.nodes.size());
        if (!m.has("setpoint")) m.fail_missing("setpoint", "(a speed channel, a constant speed in rad/s or a parameter)");
        const YAML::Node given = m.get("setpoint");
        const std::string text = given.IsScalar() ? given.Scalar() : std::string();
        const bool constant = !text.empty() && (std::isdigit(static_cast<unsigned char>(text.front())) ||
                                                text.front() == '-' || text.front() == '+' || text.front() == '.' ||
                                                net_.parameter_index(text) >= 0);
        net_.nodes.push_back(reference);
        if (constant)
            setpoint.speed = field(m, "setpoint");
        else
            setpoint.input = time_input(m, "setpoint", "a speed");
        add_speed_source(m, setpoint);
        net_.spring_dampers.push_back(SpringDamperSpec{name, setpoint.node, drive, field(m, "ki"), field(m, "kp")});
    }

    const YamlMap& model_;
    const YamlSource& src_;
    NetworkSpec net_;
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

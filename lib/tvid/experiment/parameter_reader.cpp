#include "tvid/experiment/parameter_reader.hpp"

#include "tvid/util/text.hpp"

#include <cstdio>

#include "tvid/experiment/model_reader.hpp"

namespace tvid {

namespace {

// Parameters whose value must be positive whatever the data say: inertias (and inverse
// inertias) of nodes, and the smoothing steepness σ of a clearance (φ1 divides by σ).
std::vector<const char*> positivity_roles(const NetworkSpec& n) {
    std::vector<const char*> role(n.parameter_names.size(), nullptr);
    auto set = [&](const Field& f, const char* what) {
        if (f.is_parameter()) role[static_cast<std::size_t>(f.parameter)] = what;
    };
    for (const NodeSpec& node : n.nodes) set(node.inertia, node.inverse ? "an inverse inertia" : "an inertia");
    for (const ClearanceSpec& c : n.clearances)
        if (c.smooth) set(c.sigma, "the smoothing steepness sigma");
    for (const GearMeshSpec& g : n.gear_meshes)
        if (g.has_clearance && g.smooth) set(g.sigma, "the smoothing steepness sigma");
    return role;
}

ParameterSetting read_one(const YamlMap& m, const std::string& name, const char* positive_role,
                          bool needs_search_box) {
    m.allow_only({"init", "value", "fixed", "min", "max", "range"});
    ParameterSetting p;
    p.name = name;
    p.where = m.source().where(m.node(), m.path());
    p.fixed = m.has("fixed") ? m.flag("fixed") : (m.has("value") && !m.has("init"));
    if (m.has("value") && m.has("init")) m.fail("value", "give either value (fixed) or init (free), not both");
    if (m.has("value") && !p.fixed) m.fail("value", "value is for fixed parameters; a free parameter starts at init");
    if (m.has("min")) { p.min = m.number("min"); p.has_min = true; }
    if (m.has("max")) { p.max = m.number("max"); p.has_max = true; }
    if (!p.fixed && p.has_min && p.has_max && p.min == p.max)
        m.fail("max", "min equals max: nothing is left to identify; fix the parameter with value: " + number_text(p.min));
    if (p.has_min && p.has_max && p.min > p.max)
        m.fail("min", "min (" + number_text(p.min) + ") is greater than max (" + number_text(p.max) + ")");
    if (m.has("range")) {
        const auto r = read_interval(m.source(), m.get("range"), m.key_path("range"), true);
        if (r.first < p.min || r.second > p.max)
            m.fail("range", "range [" + number_text(r.first) + ", " + number_text(r.second) +
                                "] reaches outside the bounds [" + (p.has_min ? number_text(p.min) : "-inf") + ", " +
                                (p.has_max ? number_text(p.max) : "inf") + "]");
        p.range = r;
    }
    const char* start_key = m.has("value") ? "value" : "init";
    if (m.has(start_key)) {
        p.init = m.number(start_key);
    } else if (p.fixed) {
        m.fail_missing("value", "(a fixed parameter needs its value)");
    } else if (p.range) {
        p.init = 0.5 * (p.range->first + p.range->second);
    } else if (p.has_min && p.has_max) {
        p.init = 0.5 * (p.min + p.max);
    } else if (p.has_min || p.has_max) {
        p.init = p.has_min ? p.min : p.max;
    }
    if (p.init < p.min || p.init > p.max)
        m.fail(start_key, std::string(start_key) + " " + number_text(p.init) + " is outside the bounds [" +
                              (p.has_min ? number_text(p.min) : "-inf") + ", " +
                              (p.has_max ? number_text(p.max) : "inf") + "]");
    if (positive_role != nullptr) {
        if (!(p.init > 0))
            m.fail(start_key, "must be positive: " + name + " is " + positive_role + " (got " + number_text(p.init) + ")");
        if (p.has_min && !(p.min > 0))
            m.fail("min", "must be positive: " + name + " is " + positive_role + " (got " + number_text(p.min) + ")");
        if (p.range && !(p.range->first > 0))
            m.fail("range", "must stay positive: " + name + " is " + positive_role);
    }
    if (!p.fixed && needs_search_box && !p.range && !(p.has_min && p.has_max))
        m.source().fail(m.node(), m.path(),
                        "the particle swarm needs a search box: give range: [a, b] or both min and max");
    return p;
}

}  // namespace

std::vector<ParameterSetting> read_parameters(const YamlMap& parameters, const NetworkSpec& network,
                                              bool needs_search_box) {
    const YamlSource& src = parameters.source();
    parameters.allow_only(network.parameter_names);
    const std::vector<bool> used = parameters_in_use(network);
    const std::vector<const char*> roles = positivity_roles(network);
    std::vector<ParameterSetting> out;
    for (std::size_t i = 0; i < network.parameter_names.size(); ++i) {
        const std::string& name = network.parameter_names[i];
        if (!parameters.has(name))
            parameters.fail_missing(name, "(model parameter " + name + " needs { init, min, max } or { value })");
        if (!used[i]) parameters.fail(name, "is not used by any node, element or output of the model");
        const YAML::Node node = parameters.get(name);
        if (node.IsScalar()) {  // `name: 3.5` is shorthand for a fixed value
            ParameterSetting p;
            p.name = name;
            p.fixed = true;
            p.init = read_number(src, node, parameters.key_path(name));
            p.where = src.where(node, parameters.key_path(name));
            if (roles[i] != nullptr && !(p.init > 0))
                parameters.fail(name, "must be positive: " + name + " is " + roles[i]);
            out.push_back(p);
            continue;
        }
        out.push_back(read_one(YamlMap(src, node, parameters.key_path(name)), name, roles[i], needs_search_box));
    }
    return out;
}

}  // namespace tvid

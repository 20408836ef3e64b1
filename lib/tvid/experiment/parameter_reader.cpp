#include "tvid/experiment/parameter_reader.hpp"

#include "tvid/io/atomic_file.hpp"
#include "tvid/util/text.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <utility>

#include "tvid/experiment/model_reader.hpp"
#include "tvid/model/element_traits.hpp"
#include "tvid/model/field_bounds.hpp"
#include "tvid/model/parameter_formula.hpp"

namespace tvid {

namespace {

// What a parameter is physically, where that limits its sign: inertias (and inverse
// inertias), the smoothing steepness σ of a clearance (φ1 divides by σ) and cylinder
// dimensions must be positive; stiffnesses, damping and friction coefficients, a
// clearance's half backlash μ and a reciprocating mass cannot be negative (a negative
// damping feeds energy in, a negative inertia or stiffness turns an oscillation into
// exponential growth); a gear ratio must not be zero. Parameters with no such meaning
// (offsets) have no role.
struct PhysicalRole {
    const char* what = nullptr;  ///< e.g. "an inertia"; nullptr: any sign
    SignRule sign = SignRule::any;
};

std::vector<PhysicalRole> physical_roles(const NetworkSpec& n) {
    std::vector<PhysicalRole> role(n.parameter_names.size());
    auto set = [&](const Field& f, const char* what, SignRule sign) {
        if (!f.is_parameter()) return;
        PhysicalRole& r = role[static_cast<std::size_t>(f.parameter)];
        if (r.what != nullptr && r.sign != SignRule::non_negative) return;  // a stricter rule stays
        r = PhysicalRole{what, sign};
    };
    for (const NodeSpec& node : n.nodes)
        set(node.inertia, node.inverse ? "an inverse inertia" : "an inertia", SignRule::positive);
    // Each element kind's field table says which sign its fields' physics allows.
    for_each_element_field(n, [&](const FieldInfo& info, const Field& f) {
        if (info.sign != SignRule::any) set(f, info.role, info.sign);
    });
    return role;
}

// "must be positive", "cannot be negative" or "must not be zero", as the role asks.
bool violates(const PhysicalRole& role, double v) { return violates_sign(role.sign, v); }

std::string role_problem(const PhysicalRole& role, const std::string& name, double v) {
    return std::string(sign_problem(role.sign)) + name + " is " + role.what + " (got " + number_text(v) + ")";
}

// A free parameter that must not be zero (a gear ratio) searches one side of 0 only:
// its bounds, and its range, must neither straddle nor touch 0.
void check_one_side_of_zero(const YamlMap& m, const ParameterSetting& p, const PhysicalRole& role) {
    if (role.sign != SignRule::nonzero || p.fixed) return;
    const auto problem = [&](double lo, double hi, bool lo_given, bool hi_given) {
        return "the bounds [" + (lo_given ? number_text(lo) : std::string("-inf")) + ", " +
               (hi_given ? number_text(hi) : std::string("inf")) + "] reach 0: " + p.name + " is " + role.what +
               ", which must not be zero; keep them on one side of 0 (min > 0 or max < 0)";
    };
    if (!((p.has_min && p.min > 0) || (p.has_max && p.max < 0))) {
        const std::string message = problem(p.min, p.max, p.has_min, p.has_max);
        if (p.has_min) m.fail("min", message);
        if (p.has_max) m.fail("max", message);
        m.source().fail(m.node(), m.path(), message);
    }
    if (p.range && !(p.range->first > 0 || p.range->second < 0))
        m.fail("range", problem(p.range->first, p.range->second, true, true));
}

// The bounds of an element's fields once the parameters are read: a fixed parameter's
// value, a free one's [min, max] (unbounded where a bound is not given). A rule an element
// kind checks between its fields (elements/NAME.hpp, check) is broken here by bounds that
// let some value break it, and reported at the first parameter it involves.
class ParameterFieldBounds final : public FieldBounds {
public:
    ParameterFieldBounds(const YamlMap& parameters, const std::vector<ParameterSetting>& settings,
                         std::string element)
        : parameters_(parameters), settings_(settings), element_(std::move(element)) {}
    bool known(const Field&) const override { return true; }
    double lowest(const Field& f) const override {
        if (!f.is_parameter()) return f.constant;
        const ParameterSetting& p = setting(f);
        return p.fixed ? p.init : p.has_min ? p.min : -std::numeric_limits<double>::infinity();
    }
    double highest(const Field& f) const override {
        if (!f.is_parameter()) return f.constant;
        const ParameterSetting& p = setting(f);
        return p.fixed ? p.init : p.has_max ? p.max : std::numeric_limits<double>::infinity();
    }
    std::string text(const Field& f) const override {
        if (!f.is_parameter()) return number_text(f.constant);
        const ParameterSetting& p = setting(f);
        if (p.fixed) return p.name + " = " + number_text(p.init);
        return p.name + " (bounds [" + (p.has_min ? number_text(p.min) : std::string("-inf")) + ", " +
               (p.has_max ? number_text(p.max) : std::string("inf")) + "])";
    }
    [[noreturn]] void fail(const char* key, std::initializer_list<Field> involved,
                           const std::string& problem) const override {
        std::string name;
        for (const Field& f : involved)
            if (f.is_parameter()) {
                name = setting(f).name;
                break;
            }
        parameters_.fail(name, "its bounds break a rule of element '" + element_ + "': " + key + ": " + problem);
    }

private:
    const ParameterSetting& setting(const Field& f) const { return settings_[static_cast<std::size_t>(f.parameter)]; }
    const YamlMap& parameters_;
    const std::vector<ParameterSetting>& settings_;
    std::string element_;
};

// Each element with a parameter among its fields keeps its kind's rules for every value of
// the parameters' bounds (limits that hold zero, stage angles in order, ...).
void check_element_rules(const YamlMap& parameters, const NetworkSpec& network,
                         const std::vector<ParameterSetting>& settings) {
    for_each_element(network, [&](auto kind, const auto& e) {
        using K = decltype(kind);
        if constexpr (requires(const FieldBounds& b) { K::check(e, b); }) {
            bool has_parameter = false;
            K::for_each_field([&](const FieldInfo& info, const Field& f) { has_parameter |= info.in_use && f.is_parameter(); },
                              e);
            if (has_parameter) K::check(e, ParameterFieldBounds(parameters, settings, e.name));
        }
    });
}

ParameterSetting read_one(const YamlMap& m, const std::string& name, const PhysicalRole& role,
                          bool needs_search_box) {
    m.allow_only({"init", "value", "fixed", "min", "max", "range", "scale"});
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
    if (role.what != nullptr && role.sign != SignRule::nonzero) {
        if (violates(role, p.init)) m.fail(start_key, role_problem(role, name, p.init));
        if (p.has_min && violates(role, p.min)) m.fail("min", role_problem(role, name, p.min));
        if (p.range && violates(role, p.range->first))
            m.fail("range", std::string(role.sign == SignRule::non_negative ? "must not reach below 0: "
                                                                            : "must stay positive: ") +
                                name + " is " + role.what);
    }
    if (role.sign == SignRule::nonzero) {
        check_one_side_of_zero(m, p, role);
        if (violates(role, p.init)) m.fail(start_key, role_problem(role, name, p.init));
    }
    if (m.has("scale")) {
        const std::string scale = m.text("scale");
        if (scale == "log") p.scale = ParameterScale::log;
        else if (scale != "linear") m.fail("scale", "expected log or linear, got '" + scale + "'");
        if (p.scale == ParameterScale::log && !(p.has_min && p.min > 0))
            m.fail("scale", "scale: log searches the logarithm of " + name +
                                ", whose box must stay positive: give min > 0 (" +
                                (p.has_min ? "min is " + number_text(p.min) : std::string("no min is given")) + ")");
    }
    if (!p.fixed && needs_search_box && !p.range && !(p.has_min && p.has_max))
        m.source().fail(m.node(), m.path(),
                        "the particle swarm needs a search box: give range: [a, b] or both min and max");
    return p;
}

}  // namespace

namespace {

// The formulas of the parameters given as `{ expr: "…" }`, in the order they resolve.
std::vector<ParameterFormula> read_formulas(const YamlMap& parameters, const NetworkSpec& network) {
    const YamlSource& src = parameters.source();
    std::vector<ParameterFormula> expressions;
    for (std::size_t i = 0; i < network.parameter_names.size(); ++i) {
        const std::string& name = network.parameter_names[i];
        if (!parameters.has(name) || !parameters.get(name).IsMap()) continue;
        const YamlMap m(src, parameters.get(name), parameters.key_path(name));
        if (!m.has("expr")) continue;
        m.allow_only({"expr"});  // a formula's value is its own: no init, bounds or range
        try {
            expressions.push_back(compile_parameter_formula(m.text("expr"), network.parameter_names,
                                                               static_cast<int>(i)));
        } catch (const std::invalid_argument& e) {
            m.fail("expr", e.what());
        }
    }
    try {
        return order_parameter_formulas(std::move(expressions), network.parameter_names);
    } catch (const std::invalid_argument& e) {
        const std::string first = std::string(e.what()).substr(std::string(e.what()).find(": ") + 2);
        const std::string name = first.substr(0, first.find(' '));
        const YamlMap m(src, parameters.get(name), parameters.key_path(name));
        m.fail("expr", e.what());
    }
}

}  // namespace

std::vector<ParameterSetting> read_parameters(const YamlMap& parameters, NetworkSpec& network,
                                              bool needs_search_box) {
    const YamlSource& src = parameters.source();
    parameters.allow_only(network.parameter_names);
    const std::vector<ParameterFormula> expressions = read_formulas(parameters, network);
    std::vector<bool> used = parameters_in_use(network);
    for (const ParameterFormula& e : expressions)  // a parameter a formula reads is in use
        for (int r : e.reads) used[static_cast<std::size_t>(r)] = true;
    const std::vector<PhysicalRole> roles = physical_roles(network);
    std::vector<ParameterSetting> out;
    for (std::size_t i = 0; i < network.parameter_names.size(); ++i) {
        const std::string& name = network.parameter_names[i];
        if (!parameters.has(name))
            parameters.fail_missing(name, "(model parameter " + name + " needs { init, min, max }, { value } or { expr })");
        if (const std::string why = plain_name_problem(name); !why.empty()) parameters.fail(name, why);
        if (!used[i]) parameters.fail(name, "is not used by any node, element, output or formula of the model");
        const YAML::Node node = parameters.get(name);
        if (const auto e = std::find_if(expressions.begin(), expressions.end(),
                                        [&](const ParameterFormula& x) { return x.parameter == static_cast<int>(i); });
            e != expressions.end()) {
            ParameterSetting p;
            p.name = name;
            p.fixed = true;  // held: the formula gives its value
            p.expr = e->text;
            p.where = src.where(node, parameters.key_path(name));
            out.push_back(p);
            continue;
        }
        if (node.IsScalar()) {  // `name: 3.5` is shorthand for a fixed value
            ParameterSetting p;
            p.name = name;
            p.fixed = true;
            p.init = read_number(src, node, parameters.key_path(name));
            p.where = src.where(node, parameters.key_path(name));
            if (roles[i].what != nullptr && violates(roles[i], p.init))
                parameters.fail(name, role_problem(roles[i], name, p.init));
            out.push_back(p);
            continue;
        }
        out.push_back(read_one(YamlMap(src, node, parameters.key_path(name)), name, roles[i], needs_search_box));
    }
    // A formula's value at the others' init values, held to its physical role there.
    std::vector<double> init(out.size());
    for (std::size_t i = 0; i < out.size(); ++i) init[i] = out[i].init;
    resolve_parameter_formulas(expressions, init.data());
    for (const ParameterFormula& e : expressions) {
        const auto i = static_cast<std::size_t>(e.parameter);
        out[i].init = init[i];
        const YamlMap m(src, parameters.get(out[i].name), parameters.key_path(out[i].name));
        if (!std::isfinite(init[i])) m.fail("expr", "is " + number_text(init[i]) + " at the other parameters' init values");
        if (roles[i].what != nullptr && violates(roles[i], init[i]))
            m.fail("expr", role_problem(roles[i], out[i].name, init[i]) + " at the other parameters' init values");
    }
    network.parameter_formulas = expressions;
    check_element_rules(parameters, network, out);
    return out;
}

std::optional<std::pair<double, double>> search_interval(const ParameterSetting& p) {
    if (p.range) return p.range;
    if (p.has_min && p.has_max) return std::make_pair(p.min, p.max);
    return std::nullopt;
}

bool spans_decades(const ParameterSetting& p, double decades) {
    if (p.fixed || p.scale != ParameterScale::linear) return false;
    const auto box = search_interval(p);
    return box && box->first > 0 && box->second > box->first * std::pow(10.0, decades);
}

std::string parameter_value_problem(const NetworkSpec& network, const ParameterSetting& setting, std::size_t index,
                                    double value) {
    const std::vector<PhysicalRole> roles = physical_roles(network);
    if (index < roles.size() && roles[index].what != nullptr && violates(roles[index], value))
        return role_problem(roles[index], setting.name, value);
    if (!setting.fixed && ((setting.has_min && value < setting.min) || (setting.has_max && value > setting.max)))
        return number_text(value) + " is outside the bounds of " + setting.name + " in the experiment (" +
               (setting.has_min ? number_text(setting.min) : std::string("-inf")) + " to " +
               (setting.has_max ? number_text(setting.max) : std::string("inf")) + ")";
    return {};
}

}  // namespace tvid

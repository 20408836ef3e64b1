#include "tvid/model/network_spec.hpp"

#include <algorithm>

namespace tvid {

namespace {
template <class Range, class Name>
int find_index(const Range& range, Name name_of, const std::string& wanted) {
    for (std::size_t i = 0; i < range.size(); ++i)
        if (name_of(range[i]) == wanted) return static_cast<int>(i);
    return -1;
}
}  // namespace

int NetworkSpec::parameter_index(const std::string& name) const {
    return find_index(parameter_names, [](const std::string& s) { return s; }, name);
}
int NetworkSpec::input_index(const std::string& name) const {
    return find_index(input_names, [](const std::string& s) { return s; }, name);
}
int NetworkSpec::output_index(const std::string& name) const {
    return find_index(outputs, [](const OutputSpec& o) { return o.name; }, name);
}
int NetworkSpec::node_index(const std::string& name) const {
    return find_index(nodes, [](const NodeSpec& n) { return n.name; }, name);
}

bool NetworkSpec::find_element(const std::string& name, ElementRef& ref) const {
    bool found = false;
    for_each_element_kind([&](auto kind) {
        if (found) return;
        using Row = ElementRow<decltype(kind)>;
        const int i = find_index(Row::list(*this), [](const auto& e) { return e.name; }, name);
        if (i >= 0) {
            ref = ElementRef{Row::kind, i};
            found = true;
        }
    });
    return found;
}

std::array<std::size_t, kElementKindCount> element_counts(const NetworkSpec& n) {
    std::array<std::size_t, kElementKindCount> counts{};
    for_each_element_kind([&](auto kind) {
        using Row = ElementRow<decltype(kind)>;
        counts[static_cast<std::size_t>(Row::kind)] = Row::list(n).size();
    });
    return counts;
}

const char* element_kind_name(ElementKind kind) {
    const char* name = "";
    for_each_element_kind([&](auto k) {
        using Row = ElementRow<decltype(k)>;
        if (Row::kind == kind) name = decltype(k)::type_name;
    });
    return name;
}

bool element_has_output_side(ElementKind kind) {
    bool has = false;
    for_each_element_kind([&](auto k) {
        using K = decltype(k);
        if (ElementRow<K>::kind == kind) has = K::outputs == ElementOutputs::torque_each_side;
    });
    return has;
}

bool prescribes_motion(const NetworkSpec& n) {
    bool prescribes = false;
    for_each_element_kind([&](auto k) {
        using K = decltype(k);
        if constexpr (requires(const typename K::template Bound<double>& e, const double* u) { K::prescribed_speed(e, u); })
            prescribes = prescribes || !ElementRow<K>::list(n).empty();
    });
    return prescribes;
}

bool has_sampled_elements(const NetworkSpec& n) {
    bool sampled = false;
    for_each_element_kind([&](auto k) {
        using K = decltype(k);
        if constexpr (requires(const typename K::Spec& s) { K::sampled(s); })
            for (const auto& s : ElementRow<K>::list(n)) sampled = sampled || K::sampled(s);
    });
    return sampled;
}

std::vector<std::string> state_nodes(const NetworkSpec& n) {
    std::vector<std::string> names;
    for (const NodeSpec& node : n.nodes)
        if (node.holds_state) names.push_back(node.name);
    return names;
}

namespace {

/// trait(K{}) of output kind `kind`'s row.
template <class Trait>
auto output_trait(OutputKind kind, Trait&& trait) {
    decltype(trait(outputs::Speed{})) value{};
    for_each_output_kind([&](auto k) {
        if (OutputRow<decltype(k)>::kind == kind) value = trait(k);
    });
    return value;
}

}  // namespace

const char* output_kind_key(OutputKind kind) {
    return output_trait(kind, []<class K>(K) { return K::key; });
}

const char* output_kind_unit(OutputKind kind, bool linear) {
    return output_trait(kind, [linear]<class K>(K) { return linear ? K::linear_unit : K::unit; });
}

bool output_is_speed(OutputKind kind) {
    return output_trait(kind, []<class K>(K) { return K::is_speed; });
}

bool output_is_angle(OutputKind kind) {
    return output_trait(kind, []<class K>(K) { return K::is_angle; });
}

bool output_reads_node(OutputKind kind) {
    return output_trait(kind, []<class K>(K) { return K::target == outputs::Target::node; });
}

}  // namespace tvid

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

}  // namespace tvid

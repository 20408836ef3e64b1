#pragma once
// Reading one element of a kind of the table into a network, the same way for every kind:
// its own read (elements/NAME.hpp), the sign checks of its field table, its own further
// checks, and its rules against the others of its kind. The experiment floor walks the
// table with these (experiment/model_reader.cpp); composite kinds (elements/composite_kinds.hpp)
// add their parts with add_element.

#include <string>
#include <utility>
#include <vector>

#include "tvid/model/element_source.hpp"
#include "tvid/model/element_traits.hpp"
#include "tvid/model/network_spec.hpp"
#include "tvid/util/text.hpp"

namespace tvid {

/// The keys an entry of kind K may give: type, name and the kind's own.
template <class K>
std::vector<std::string> element_keys() {
    std::vector<std::string> keys{"type", "name"};
    for (const char* key : K::keys) keys.emplace_back(key);
    return keys;
}

/// A constant field must keep the sign its kind's field table asks for (a parameter is
/// checked with the parameters). A field given by its shorthand (a clearance law's k for
/// k_minus) is reported at the key that was given.
template <class K>
void check_field_signs(const ElementSource& src, const typename K::Spec& e) {
    K::for_each_field(
        [&](const FieldInfo& info, const Field& f) {
            if (!info.in_use || f.is_parameter() || !violates_sign(info.sign, f.constant)) return;
            std::string key = info.name;
            if (!src.has(key) && info.shorthand != nullptr) key = info.shorthand;
            src.fail(key, std::string(sign_problem(info.sign)) + info.role + " (got " + number_text(f.constant) + ")");
        },
        e);
}

/// Appends e to its kind's list, after the kind's rules against the others of its kind
/// (K::check_against: a node's speed is prescribed once).
template <class K>
void add_element(const ElementSource& src, NetworkSpec& net, typename K::Spec e) {
    auto& list = ElementRow<K>::list(net);
    if constexpr (requires { K::check_against(e, list, src); }) K::check_against(e, list, src);
    list.push_back(std::move(e));
}

/// Reads the element `name` of kind K from src into net.
template <class K>
void read_element(ElementSource& src, const std::string& name, NetworkSpec& net) {
    typename K::Spec e = K::read(src, name);
    check_field_signs<K>(src, e);
    if constexpr (requires { K::check(e, ConstantFieldBounds(src)); }) K::check(e, ConstantFieldBounds(src));
    if constexpr (requires { K::add_parts(e, src, net); }) K::add_parts(e, src, net);  // hidden nodes it needs
    add_element<K>(src, net, std::move(e));
}

/// Once every element is read: the kinds' last steps over their lists (K::finish_reading:
/// a speed channel's slope becomes an input).
inline void finish_reading(NetworkSpec& net) {
    for_each_element_kind([&](auto kind) {
        using K = decltype(kind);
        if constexpr (requires { K::finish_reading(ElementRow<K>::list(net), net.input_rates, net.input_names.size()); })
            K::finish_reading(ElementRow<K>::list(net), net.input_rates, net.input_names.size());
    });
}

}  // namespace tvid

#include "tvid/model/element_catalogue.hpp"

#include <iterator>

#include "tvid/model/elements/composite_kinds.hpp"
#include "tvid/model/network_spec.hpp"

namespace tvid {

namespace {

const char* sign_text(SignRule rule) {
    switch (rule) {
        case SignRule::any: return "any";
        case SignRule::non_negative: return ">= 0";
        case SignRule::positive: return "> 0";
        case SignRule::nonzero: return "!= 0";
    }
    return "any";
}

template <class K>
ElementKindDoc kind_doc(bool composite) {
    ElementKindDoc doc;
    doc.type = K::type_name;
    doc.summary = K::summary;
    doc.composite = composite;
    for (const char* key : K::keys) doc.keys.emplace_back(key);
    return doc;
}

}  // namespace

std::vector<ElementKindDoc> element_kind_catalogue() {
    std::vector<ElementKindDoc> out;
    for_each_element_kind([&](auto kind) {
        using K = decltype(kind);
        ElementKindDoc doc = kind_doc<K>(false);
        typename K::Spec spec{};
        K::for_each_field(
            [&](const FieldInfo& info, const Field&) {
                doc.fields.push_back({info.name, info.role ? info.role : "", info.unit, sign_text(info.sign)});
            },
            spec);
        out.push_back(std::move(doc));
    });
    for_each_composite_kind([&](auto kind) {
        using K = decltype(kind);
        ElementKindDoc doc = kind_doc<K>(true);
        if constexpr (requires { K::fields; })
            for (const FieldInfo& info : K::fields)
                doc.fields.push_back({info.name, info.role ? info.role : "", info.unit, sign_text(info.sign)});
        out.push_back(std::move(doc));
    });
    return out;
}

}  // namespace tvid

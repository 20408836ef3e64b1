#pragma once
// What the experiment file's element kinds are, for `tvid models` and the docs: each kind's
// type name, one line on what it is, its keys, and its numeric fields with their units and
// sign rules, read from the kinds' own files (elements/element_kinds.hpp and
// elements/composite_kinds.hpp).

#include <string>
#include <vector>

namespace tvid {

struct ElementFieldDoc {
    std::string key;   ///< in the experiment file
    std::string role;  ///< what it is physically ("a stiffness"), or empty
    std::string unit;  ///< SI
    std::string sign;  ///< "any", ">= 0", "> 0" or "!= 0"
};

struct ElementKindDoc {
    std::string type;       ///< `type:` in the experiment file
    std::string summary;
    std::vector<std::string> keys;        ///< every key it reads besides type and name
    std::vector<ElementFieldDoc> fields;  ///< its numeric fields (a number or a parameter); a composite kind's as it declares them
    bool composite = false;  ///< built from other kinds' nodes and elements (a speed controller)
};

/// Every element kind, then every composite kind, in their tables' order.
std::vector<ElementKindDoc> element_kind_catalogue();

}  // namespace tvid

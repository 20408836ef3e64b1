#pragma once
// The composite kinds of the experiment file, one row each: a `type:` that the reader
// builds from nodes and elements of the kinds of element_kinds.hpp rather than a kind of
// its own (a speed controller: a reference node, a speed source and a spring-damper). Each
// type (elements/NAME.hpp) declares type_name, keys and build(ElementSource&, name, NetworkSpec&).
//
// Adding a composite kind: write elements/NAME.hpp (as speed_controller.hpp) and add its row.

#include <tuple>

#include "tvid/model/elements/speed_controller.hpp"

//     X(Type)
#define TVID_COMPOSITE_KINDS(X) X(SpeedController)

namespace tvid {

/// Every composite type (tvid::elements::…), in the table's order.
using CompositeTypes = decltype(std::tuple_cat(
#define TVID_COMPOSITE_TYPE(Type) std::tuple<elements::Type>{},
    TVID_COMPOSITE_KINDS(TVID_COMPOSITE_TYPE)
#undef TVID_COMPOSITE_TYPE
        std::tuple<>{}));

/// f(K{}) for each composite type K, in the table's order.
template <class F>
void for_each_composite_kind(F&& f) {
    std::apply([&](auto... kind) { (f(kind), ...); }, CompositeTypes{});
}

}  // namespace tvid

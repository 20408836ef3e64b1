#pragma once
// The load of an element between two nodes, or a node and ground: its torque t acts on node
// a against its sign and on node b (when not ground) with it. The kinds between two nodes
// (spring-damper, clearance, friction, multistage spring) take it by deriving from
// TwoNodeLoad; a kind with another load (a torque on one node, a gear's two shafts, a
// cylinder's crank) defines its own `load`.

#include "tvid/model/field.hpp"
#include "tvid/model/elements/node_motion.hpp"

namespace tvid::elements {

struct TwoNodeLoad {
    /// e: the bound element (its nodes a and b); t: its torque.
    template <class B, class T>
    [[gnu::always_inline]] static void load(const B& e, const T& t, const NodeMotion<T>&, T* node_torque) {
        node_torque[e.a] -= t;
        if (e.b != kGround) node_torque[e.b] += t;
    }
};

}  // namespace tvid::elements

#pragma once
// What every element kind declares besides its torque (lib/tvid/model/elements/NAME.hpp):
// the channel it reads, the outputs it offers and how it enters a linearisation about an
// operating point (modes and FRF). ElementKindDescription (network_spec.hpp) checks at
// compile time that each kind of the table declares them.

#include <cstdio>
#include <cstdlib>
#include <string>
#include <tuple>
#include <type_traits>
#include <vector>

#include "tvid/model/element_source.hpp"
#include "tvid/model/field.hpp"
#include "tvid/model/field_bounds.hpp"

namespace tvid {

/// The measured channel an element kind reads: its SI unit (nullptr: it reads none), and
/// whether it is read by crank angle (a cylinder pressure) rather than by time.
struct ChannelUse {
    const char* unit = nullptr;
    bool by_angle = false;
};

/// The outputs an element offers: its torque, or its torque on either side (a gear mesh:
/// T on its input shaft, n·T on its output shaft; the kind defines output_side_torque), or
/// none (an ideal gear: its torque is a constraint's).
enum class ElementOutputs { torque, torque_each_side, none };

/// Where an element acts, as its kind declares it (`static constexpr ElementEnds ends`):
/// at its one node (its spec's `node`); between its nodes `a` and `b` (b may be kGround);
/// or between them through a gear, whose `ratio` ties the speeds at rest (ω_a = ratio·ω_b).
enum class ElementEnds { one_node, two_nodes, geared };

/// The nodes of a bound element, as its kind's `ends` declare them: each kind's Bound
/// derives from BoundEnds<ends> (OnOneNode or BetweenTwoNodes; DescribedElementKind checks
/// it), and binding copies them from the spec (bind_ends) before the kind's own bind, if it
/// has one, sees the element.
struct OnOneNode {
    int node = 0;
};
struct BetweenTwoNodes {
    int a = 0, b = kGround;
};
template <ElementEnds E>
using BoundEnds = std::conditional_t<E == ElementEnds::one_node, OnOneNode, BetweenTwoNodes>;

template <class Kind, class Bound>
void bind_ends(const typename Kind::Spec& s, Bound& e) {
    if constexpr (Kind::ends == ElementEnds::one_node) {
        e.node = s.node;
    } else {
        e.a = s.a;
        e.b = s.b;
    }
}

/// A spec of kind Kind named `name`, at the nodes its `ends` declare, as the file gives them:
/// `node: N` for one node; `between: [a, b]` for two (`[a]` or `[a, ground]`: b is ground);
/// `between: [a, b]` and `ratio: N` across a gear (two shafts, neither ground). A kind's read
/// starts from it (friction, on `node:` or `between:`, reads its own).
template <class Kind>
typename Kind::Spec spec_at_ends(const ElementSource& src, const std::string& name) {
    typename Kind::Spec e;
    e.name = name;
    if constexpr (Kind::ends == ElementEnds::one_node)
        e.node = src.node("node");
    else
        std::tie(e.a, e.b) = src.between(Kind::ends == ElementEnds::two_nodes);
    if constexpr (Kind::ends == ElementEnds::geared) e.ratio = src.field("ratio");
    return e;
}

/// How the elements that depend on a node's absolute angle (a cylinder's slider crank and
/// gas torque, an order torque) are linearised.
enum class AngleDependence {
    revolution_mean,  ///< at their mean over a revolution (a cycle): the cylinder's inertia m·mean(s'²), excitations no stiffness
    operating_point,  ///< at the operating point's angle, as the equations are there
};

/// How one element entered the linearisation.
struct ElementLinearisation {
    std::string element;  ///< its name
    std::string kind;     ///< spring_damper, clearance, …
    std::string method;   ///< exact, operating_point, revolution_mean, excitation, prescribed
    std::string note;     ///< a sentence for the engineer
};

/// How a kind says its element entered the linearisation (the walker adds the element's
/// name and kind).
struct LinearNote {
    std::string method;  ///< exact, operating_point, revolution_mean, excitation, prescribed
    std::string note;
};

/// What a kind's linearise() sees and may change besides its own element: the parameters,
/// the operating point x̄ (full state), the mode, the nodes' names, the inertia its
/// element adds to a node and the nodes whose speed is prescribed.
struct LinearisationPoint {
    const std::vector<double>& p;
    const std::vector<double>& x;
    AngleDependence mode;
    const std::vector<std::string>& node_names;
    std::vector<double>& added_inertia;  ///< per node [kg m²]
    std::vector<char>& prescribed;       ///< per node: its speed is an input's

    double value(const Field& f) const { return f.is_parameter() ? p[static_cast<std::size_t>(f.parameter)] : f.constant; }
    double angle(int node) const { return x[static_cast<std::size_t>(node)]; }
    std::string node_name(int i) const { return i == kGround ? std::string("ground") : node_names[static_cast<std::size_t>(i)]; }
    /// θa − ratio·θb at the operating point (θa for b = ground).
    double twist(int a, int b, double ratio = 1.0) const { return angle(a) - (b == kGround ? 0.0 : ratio * angle(b)); }
};

/// A number as a linearisation note writes it (%.6g).
inline std::string linear_number(double v) {
    char text[32];
    std::snprintf(text, sizeof text, "%.6g", v);
    return text;
}

/// A number a user gave, as it reads back exactly: the fewest significant digits (6 at
/// least) that round-trip, so that a refusal of 1.0000001 against a limit of 1 does not
/// print "got 1".
inline std::string given_number(double v) {
    char text[32];
    for (int digits = 6; digits <= 17; ++digits) {
        std::snprintf(text, sizeof text, "%.*g", digits, v);
        if (std::strtod(text, nullptr) == v) break;
    }
    return text;
}

/// The bounds of an element's fields while it is read: its constants, each its own value;
/// a parameter is not known yet (its rules are checked with the parameters). A broken rule
/// is reported at the element's key.
class ConstantFieldBounds final : public FieldBounds {
public:
    explicit ConstantFieldBounds(const ElementSource& src) : src_(src) {}
    bool known(const Field& f) const override { return !f.is_parameter(); }
    double lowest(const Field& f) const override { return f.constant; }
    double highest(const Field& f) const override { return f.constant; }
    std::string text(const Field& f) const override { return given_number(f.constant); }
    [[noreturn]] void fail(const char* key, std::initializer_list<Field>, const std::string& problem) const override {
        src_.fail(key, problem);
        __builtin_unreachable();  // fail() throws (a virtual [[noreturn]] call is not known to GCC as one)
    }

private:
    const ElementSource& src_;
};

}  // namespace tvid

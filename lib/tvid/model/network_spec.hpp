#pragma once
// The description of a lumped torsional network: named nodes (rotating inertias with
// angle θ and speed ω) joined by elements. Every numeric field of a node or element is
// either a constant or a reference to a model parameter; a `NetworkSpec` is built once
// (from a preset or from the experiment file) and turned into a fast `NetworkModel`
// for each parameter vector. The element kinds are the rows of
// elements/element_kinds.hpp; each kind's spec, fields and torque are in its own file
// there.

#include <array>
#include <concepts>
#include <cstddef>
#include <string>
#include <string_view>
#include <tuple>
#include <vector>

#include "tvid/model/element_source.hpp"
#include "tvid/model/element_traits.hpp"
#include "tvid/model/elements/element_kinds.hpp"
#include "tvid/model/field.hpp"
#include "tvid/model/output_kinds.hpp"
#include "tvid/model/parameter_formula.hpp"

namespace tvid {

struct NodeSpec {
    std::string name;
    Field inertia;               ///< J [kg m²], or 1/J when `inverse` is set
    bool inverse = false;        ///< the CVT paper estimates ρ1 = 1/I1
    /// `motion: linear`: a translational node written as its rotational analogue (mass as J,
    /// force as torque, position as angle); only the units it reports change (m, m/s, kg, N).
    bool linear = false;
    /// A hidden node whose speed is an element's state, not a motion (a continuous position
    /// controller's integral): a measured start leaves it at zero.
    bool holds_state = false;
};

/// The node an element of kind Kind has its fields and torque counted on: its one node, or
/// its first node `a`.
template <class Kind>
int element_node(const typename Kind::Spec& e) {
    if constexpr (Kind::ends == ElementEnds::one_node) return e.node;
    else return e.a;
}

/// An element between two nodes (ElementEnds), of which the second may be ground.
template <class Kind>
inline constexpr bool acts_between_nodes = Kind::ends != ElementEnds::one_node;

/// What every element kind's file declares (docs/architecture.md, "Adding an element"): its
/// type name and keys in the experiment file and its reader; each field's unit (FieldInfo
/// has no constructor without one); the channel it reads and its unit; the outputs it
/// offers; its linearisation for modes and FRF. A row whose kind leaves one out does not
/// compile.
template <class K>
concept DescribedElementKind = requires(ElementSource& src, const std::string& name, const typename K::Spec& spec,
                                        typename K::Spec& lin, const LinearisationPoint& at) {
    { K::type_name } -> std::convertible_to<const char*>;
    { K::summary } -> std::convertible_to<const char*>;  ///< one line for `tvid models`
    { K::keys[0] } -> std::convertible_to<const char*>;
    { K::read(src, name) } -> std::same_as<typename K::Spec>;
    { K::channel } -> std::convertible_to<ChannelUse>;
    { K::channel_of(spec) } -> std::same_as<int>;
    { K::outputs } -> std::convertible_to<ElementOutputs>;
    { K::linearise(spec, lin, at) } -> std::same_as<LinearNote>;
    { K::acts_at_rest } -> std::convertible_to<bool>;
    { K::ends } -> std::convertible_to<ElementEnds>;
    // Its spec names the nodes (and the ratio) that its ends declare.
    requires K::ends != ElementEnds::one_node || requires { { spec.node } -> std::convertible_to<int>; };
    requires K::ends == ElementEnds::one_node || requires { { spec.a } -> std::convertible_to<int>; spec.b; };
    requires K::ends != ElementEnds::geared || requires { spec.ratio; };
    // Its bound form holds the nodes its ends declare (the binding copies them, bind_ends).
    requires std::derived_from<typename K::template Bound<double>, BoundEnds<K::ends>>;
    // A kind with a torque on each side says what its output side carries.
    requires K::outputs != ElementOutputs::torque_each_side ||
                 requires(const typename K::template Bound<double>& e, const double& t,
                          const NodeMotion<double>& m) { K::output_side_torque(e, t, m); };
};

#define TVID_ELEMENT_KIND_CHECK(kind, Type, list)                                                             \
    static_assert(DescribedElementKind<elements::Type>,                                                       \
                  "elements/" #kind ".hpp leaves out a rule: type_name, summary, keys, read, channel, channel_of, "    \
                  "outputs, linearise, acts_at_rest or ends");                                                      \
    static_assert(std::string_view(#kind) == elements::Type::type_name, #kind ": its row and its type_name differ");
TVID_ELEMENT_KINDS(TVID_ELEMENT_KIND_CHECK)
#undef TVID_ELEMENT_KIND_CHECK

enum class ElementKind {
#define TVID_ELEMENT_KIND_ENUMERATOR(kind, Type, list) kind,
    TVID_ELEMENT_KINDS(TVID_ELEMENT_KIND_ENUMERATOR)
#undef TVID_ELEMENT_KIND_ENUMERATOR
};

/// Every element type (tvid::elements::…), in the table's order.
using ElementTypes = decltype(std::tuple_cat(
#define TVID_ELEMENT_TYPE(kind, Type, list) std::tuple<elements::Type>{},
    TVID_ELEMENT_KINDS(TVID_ELEMENT_TYPE)
#undef TVID_ELEMENT_TYPE
        std::tuple<>{}));

inline constexpr std::size_t kElementKindCount = std::tuple_size_v<ElementTypes>;

struct ElementRef {
    ElementKind kind;
    int index;  ///< index into the vector of that kind
};

/// The output kinds, one per row of model/output_kinds.hpp.
enum class OutputKind {
#define TVID_OUTPUT_KIND_ENUMERATOR(kind, Type) kind,
    TVID_OUTPUT_KINDS(TVID_OUTPUT_KIND_ENUMERATOR)
#undef TVID_OUTPUT_KIND_ENUMERATOR
};

/// Every output kind's type (tvid::outputs::…), in the table's order.
using OutputTypes = decltype(std::tuple_cat(
#define TVID_OUTPUT_TYPE(kind, Type) std::tuple<outputs::Type>{},
    TVID_OUTPUT_KINDS(TVID_OUTPUT_TYPE)
#undef TVID_OUTPUT_TYPE
        std::tuple<>{}));

/// What every output kind declares (model/output_kinds.hpp): its key, its unit on a rotational
/// and on a linear node, whether it is a speed or an angle, what it reads, and its value.
template <class K>
concept OutputKindTraits = requires {
    { K::key } -> std::convertible_to<const char*>;
    { K::unit } -> std::convertible_to<const char*>;
    { K::linear_unit } -> std::convertible_to<const char*>;
    { K::is_speed } -> std::convertible_to<bool>;
    { K::is_angle } -> std::convertible_to<bool>;
    { K::target } -> std::convertible_to<outputs::Target>;
};

/// The table row of output type K: its OutputKind.
template <class K>
struct OutputRow;
#define TVID_OUTPUT_ROW(kind_, Type)                                                     \
    template <>                                                                          \
    struct OutputRow<outputs::Type> {                                                    \
        static constexpr OutputKind kind = OutputKind::kind_;                            \
    };                                                                                   \
    static_assert(std::string_view(#kind_) == outputs::Type::key, #kind_ ": its row and its key differ"); \
    static_assert(OutputKindTraits<outputs::Type>, #kind_ ": declare every trait of an output kind");
TVID_OUTPUT_KINDS(TVID_OUTPUT_ROW)
#undef TVID_OUTPUT_ROW

/// f(K{}) for each output type K, in the table's order.
template <class F>
[[gnu::always_inline]] inline void for_each_output_kind(F&& f) {
    std::apply([&](auto... kind) __attribute__((always_inline)) { (f(kind), ...); }, OutputTypes{});
}

/// The experiment file's key of an output kind ("speed", …) and its SI unit ("rad/s", …)
/// on a rotational node, or on a linear one ("m/s", …).
const char* output_kind_key(OutputKind kind);
const char* output_kind_unit(OutputKind kind, bool linear = false);
/// Its traits, from its row: a speed, an angle, read on a node (else on an element).
bool output_is_speed(OutputKind kind);
bool output_is_angle(OutputKind kind);
bool output_reads_node(OutputKind kind);

/// A model output compared with a measured channel: y = gain · quantity + offset
/// (`offset` is the measurement's amplitude shift, e.g. Δds of Yoshida & Takamatsu eq. 15c;
/// `gain` the sensor's calibration factor).
struct OutputSpec {
    std::string name;
    OutputKind kind = OutputKind::speed;
    int node = 0;              ///< for speed and angle
    ElementRef element{ElementKind::spring_damper, 0};  ///< for torque
    Field offset = Field::value(0.0);
    TorqueSide side = TorqueSide::input;  ///< for torque: output only where element_has_output_side
    Field gain = Field::value(1.0);
};

struct NetworkSpec {
    std::string preset;                       ///< preset name, or "custom"
    std::vector<std::string> parameter_names; ///< model parameters, Field::parameter indexes these
    std::vector<std::string> input_names;     ///< model inputs by time, TorqueSpec::input indexes these
    std::vector<std::string> angle_input_names; ///< model inputs by crank angle, CylinderSpec::pressure indexes these
    /// Inputs whose time derivative the model reads (a speed source's acceleration): the
    /// derivative of input_rates[j] follows the inputs, at input_names.size() + j.
    std::vector<int> input_rates;
    std::vector<NodeSpec> nodes;
    // One list per element kind: spring_dampers, clearances, frictions, gear_meshes, torques, cylinders,
    // order_torques, speed_sources.
#define TVID_ELEMENT_LIST(kind, Type, list) std::vector<elements::Type::Spec> list;
    TVID_ELEMENT_KINDS(TVID_ELEMENT_LIST)
#undef TVID_ELEMENT_LIST
    std::vector<OutputSpec> outputs;          ///< every output the model offers
    /// Parameters that are a measured channel's delay [s] (ChannelBinding::delay): they move
    /// the recording against the model's time and enter no element.
    std::vector<int> delay_parameters;
    /// A parameter that is no element's but the start of an estimation window
    /// (`initial_state: { kind: estimated }`): state coordinate `state` (θ_i at i, ω_i at
    /// n + i) of estimation window `window` starts at its `from:` recipe's value plus the
    /// parameter. It enters no element either.
    struct StartCoordinate {
        int parameter = -1;
        std::size_t window = 0;
        std::size_t state = 0;
    };
    std::vector<StartCoordinate> start_coordinates;
    /// Parameters given by a formula of others (`expr:`), each after those it reads: a
    /// NetworkModel resolves them over the parameter vector it is given.
    std::vector<ParameterFormula> parameter_formulas;

    int parameter_index(const std::string& name) const;  ///< -1 if absent
    int input_index(const std::string& name) const;
    int output_index(const std::string& name) const;
    int node_index(const std::string& name) const;
    /// The element named `name` (element names are unique across kinds); false if absent.
    bool find_element(const std::string& name, ElementRef& ref) const;
    std::size_t state_size() const { return 2 * nodes.size(); }
};

/// The table row of element type K: its ElementKind, its name and its list in a NetworkSpec.
template <class K>
struct ElementRow;
#define TVID_ELEMENT_ROW(kind_, Type, list_)                                                              \
    template <>                                                                                           \
    struct ElementRow<elements::Type> {                                                                   \
        static constexpr ElementKind kind = ElementKind::kind_;                                           \
        static constexpr const char* name = #kind_;                                                       \
        static std::vector<elements::Type::Spec>& list(NetworkSpec& n) { return n.list_; }                \
        static const std::vector<elements::Type::Spec>& list(const NetworkSpec& n) { return n.list_; }    \
    };
TVID_ELEMENT_KINDS(TVID_ELEMENT_ROW)
#undef TVID_ELEMENT_ROW

/// f(K{}) for each element type K, in the table's order.
/// Inlined throughout, with the lambdas given to it marked always_inline: the
/// right-hand side walks the kinds this way.
template <class F>
[[gnu::always_inline]] inline void for_each_element_kind(F&& f) {
    std::apply([&](auto... kind) __attribute__((always_inline)) { (f(kind), ...); }, ElementTypes{});
}

/// f(K{}, spec) for each element of `n`, kind by kind in the table's order.
template <class F>
void for_each_element(const NetworkSpec& n, F&& f) {
    for_each_element_kind([&](auto kind) {
        for (const auto& e : ElementRow<decltype(kind)>::list(n)) f(kind, e);
    });
}

/// f(info, field) for each numeric field of each element of `n` that the element uses
/// (a non-smooth clearance leaves σ unused, a gear mesh without backlash its clearance fields).
template <class F>
void for_each_element_field(const NetworkSpec& n, F&& f) {
    for_each_element(n, [&](auto kind, const auto& e) {
        decltype(kind)::for_each_field(
            [&](const FieldInfo& info, const Field& field) {
                if (info.in_use) f(info, field);
            },
            e);
    });
}

/// How many elements of each kind `n` has, in the table's order.
std::array<std::size_t, kElementKindCount> element_counts(const NetworkSpec& n);

/// The experiment file's name of an element kind ("spring_damper", …).
const char* element_kind_name(ElementKind kind);

/// Whether elements of this kind carry a different torque on their output side
/// (ElementOutputs::torque_each_side: a gear mesh).
bool element_has_output_side(ElementKind kind);

/// Whether some element of n prescribes its node's motion (a speed source).
bool prescribes_motion(const NetworkSpec& n);

/// Whether some element of n samples the line at instants and holds its output between
/// them (a digital controller: its kind's `sampled(spec)` says so).
bool has_sampled_elements(const NetworkSpec& n);

/// The hidden nodes whose speed is an element's state rather than a motion
/// (NodeSpec::holds_state: a continuous position controller's integral), by name.
std::vector<std::string> state_nodes(const NetworkSpec& n);

/// The start coordinate that parameter `parameter` of n is, or nullptr for a model parameter.
inline const NetworkSpec::StartCoordinate* start_coordinate(const NetworkSpec& n, std::size_t parameter) {
    for (const NetworkSpec::StartCoordinate& c : n.start_coordinates)
        if (static_cast<std::size_t>(c.parameter) == parameter) return &c;
    return nullptr;
}

}  // namespace tvid

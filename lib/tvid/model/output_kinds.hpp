#pragma once
// The output kinds of a network, one row each: what a model output measures, the key
// that names it in the experiment file (`speed: NODE`), its SI unit on a rotational and on
// a linear node (motion: linear), whether it is a speed or an angle (what the loader's
// checks and the starts read from measured channels), whether it reads a node or an
// element, and its value in the simulation. OutputKind, the reader of the
// `outputs:` section, the units of the reports and of the FRF, and NetworkModel's
// outputs all walk this table.
//
// Adding an output kind: write its struct here (as Speed) and add its row.

namespace tvid {

/// Which shaft a torque output reads for an element whose two sides carry different
/// torques (a gear mesh: T on its input shaft a, n·T on its output shaft b).
enum class TorqueSide { input, output };

namespace outputs {

/// What an output names in the experiment file: a node (`speed: NODE`) or an element (`torque: ELEMENT`).
enum class Target { node, element };

/// The speed ω of a node [rad/s].
struct Speed {
    static constexpr const char* key = "speed";
    static constexpr const char* unit = "rad/s";
    static constexpr const char* linear_unit = "m/s";
    static constexpr bool is_speed = true, is_angle = false;
    static constexpr Target target = Target::node;
    /// o: the OutputSpec; element_torque(ref, side): an element's torque on that side.
    template <class T, class O, class ElementTorque>
    [[gnu::always_inline]] static T value(const O& o, const T*, const T* omega, ElementTorque&&) {
        return omega[o.node];
    }
};

/// The angle θ of a node [rad].
struct Angle {
    static constexpr const char* key = "angle";
    static constexpr const char* unit = "rad";
    static constexpr const char* linear_unit = "m";
    static constexpr bool is_speed = false, is_angle = true;
    static constexpr Target target = Target::node;
    template <class T, class O, class ElementTorque>
    [[gnu::always_inline]] static T value(const O& o, const T* theta, const T*, ElementTorque&&) {
        return theta[o.node];
    }
};

/// The torque an element transmits [N m], on its input side or (a gear mesh) its output side.
struct Torque {
    static constexpr const char* key = "torque";
    static constexpr const char* unit = "N m";
    static constexpr const char* linear_unit = "N";  ///< a force, on a linear node
    static constexpr bool is_speed = false, is_angle = false;
    static constexpr Target target = Target::element;
    template <class T, class O, class ElementTorque>
    [[gnu::always_inline]] static T value(const O& o, const T*, const T*, ElementTorque&& element_torque) {
        return element_torque(o.element, o.side);
    }
};

}  // namespace outputs
}  // namespace tvid

//     X(kind, Type)
#define TVID_OUTPUT_KINDS(X) \
    X(speed, Speed)          \
    X(angle, Angle)          \
    X(torque, Torque)

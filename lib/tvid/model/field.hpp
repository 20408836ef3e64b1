#pragma once
// A numeric field of a node or an element: a constant or a model parameter, and what an
// element kind says about each of its fields (its key in the experiment file and the
// sign its physics allows).

namespace tvid {

/// A number fixed in the experiment, or the index of a model parameter.
struct Field {
    double constant = 0.0;
    int parameter = -1;  ///< index into NetworkSpec::parameter_names, or -1 for a constant

    static Field value(double v) { return Field{v, -1}; }
    static Field param(int index) { return Field{0.0, index}; }
    bool is_parameter() const { return parameter >= 0; }
};

inline constexpr int kGround = -1;  ///< node index meaning "the fixed base"

/// The sign a field's physics allows: a negative stiffness or damping turns an
/// oscillation into exponential growth; a clearance's σ and a cylinder dimension are
/// divided by or must describe a real part.
enum class SignRule { any, non_negative, positive };

/// One row of an element kind's field table.
struct FieldInfo {
    const char* name;           ///< the key in the experiment file
    const char* role = nullptr; ///< what it is physically, e.g. "a stiffness" (nullptr when `sign` is any)
    SignRule sign = SignRule::any;
    bool in_use = true;         ///< false: this element leaves the field unused (e.g. σ of the non-smooth law)
};

/// Whether the constant v breaks the field's sign rule.
inline bool violates_sign(SignRule rule, double v) {
    switch (rule) {
        case SignRule::any: return false;
        case SignRule::non_negative: return !(v >= 0);
        case SignRule::positive: return !(v > 0);
    }
    return false;
}

}  // namespace tvid

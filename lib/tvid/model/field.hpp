#pragma once
// A numeric field of a node or an element: a constant or a model parameter, and what an
// element kind says about each of its fields (its key in the experiment file, the sign
// its physics allows and its SI unit).

#include <string>

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
/// divided by or must describe a real part; a gear ratio of 0 joins nothing (θa − 0·θb).
enum class SignRule { any, non_negative, positive, nonzero };

/// One row of an element kind's field table. The unit is required: a kind that leaves
/// it out does not compile.
struct FieldInfo {
    const char* name;            ///< the key in the experiment file
    const char* role = nullptr;  ///< what it is physically, e.g. "a stiffness" (nullptr when `sign` is any)
    SignRule sign = SignRule::any;
    const char* unit = "";       ///< its SI unit, e.g. "N m/rad" ("1" for a pure number)
    bool in_use = true;          ///< false: this element leaves the field unused (e.g. σ of the non-smooth law)
    const char* shorthand = nullptr;  ///< a key that may stand for it in the experiment file (k for k_minus)

    constexpr FieldInfo(const char* name_, const char* role_, SignRule sign_, const char* unit_, bool in_use_ = true,
                        const char* shorthand_ = nullptr)
        : name(name_), role(role_), sign(sign_), unit(unit_), in_use(in_use_), shorthand(shorthand_) {}
};

/// Whether the constant v breaks the field's sign rule.
inline bool violates_sign(SignRule rule, double v) {
    switch (rule) {
        case SignRule::any: return false;
        case SignRule::non_negative: return !(v >= 0);
        case SignRule::positive: return !(v > 0);
        case SignRule::nonzero: return !(v != 0);
    }
    return false;
}

/// How a broken sign rule is said: "must be positive: ", "cannot be negative: ", "must not be zero: ".
inline const char* sign_problem(SignRule rule) {
    switch (rule) {
        case SignRule::positive: return "must be positive: ";
        case SignRule::non_negative: return "cannot be negative: ";
        case SignRule::nonzero: return "must not be zero: ";
        case SignRule::any: break;
    }
    return "";
}

}  // namespace tvid

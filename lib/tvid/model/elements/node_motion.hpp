#pragma once
// What an element reads when it computes its torque: the angles and speeds of the
// nodes and the measured inputs at the current time.

#include "tvid/channels/crank_angle_channels.hpp"
#include "tvid/model/field.hpp"

namespace tvid {

template <class T>
struct NodeMotion {
    const T* theta = nullptr;
    const T* omega = nullptr;  ///< unused (may be null) at rest
    const double* u = nullptr;  ///< the inputs by time, NetworkSpec::input_names order
    const CrankAngleChannels* angle_inputs = nullptr;  ///< the inputs by crank angle
    bool in_motion = true;  ///< false: every node at rest (the static torques of an equilibrium)

    /// A flag, not a test of omega, so that the right-hand side's constant folds away.
    [[gnu::always_inline]] bool moving() const { return in_motion; }

    /// θa − θb, or θa for an element to ground.
    [[gnu::always_inline]] T twist(int a, int b) const { return difference(theta, a, b); }
    /// ωa − ωb (θ' of the twist), zero at rest.
    [[gnu::always_inline]] T twist_rate(int a, int b) const { return moving() ? difference(omega, a, b) : T(0); }

private:
    [[gnu::always_inline]] static T difference(const T* q, int a, int b) { return b == kGround ? q[a] : q[a] - q[b]; }
};

}  // namespace tvid

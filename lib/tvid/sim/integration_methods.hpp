#pragma once
// The integration methods, one row each, as elements and optimizers have theirs: the name
// that `simulation.method` gives, whether the method takes fixed steps on the sample grid
// (split by `simulation.step`), whether those steps are classical RK4's (what the SIMD
// lanes, the packed sensitivities, the shooting's Newton warm-up and the step-stability
// guard are written for), whether it uses the model's state Jacobian, and what a failed
// candidate's message suggests. How each steps is in
// sim/simulate.hpp (simulate_samples dispatches on the method).
//
// Adding a method: its enumerator, its row here, and its march in simulate_samples.

#include <array>
#include <cstddef>
#include <string_view>

#include "tvid/util/kind_table.hpp"

namespace tvid {

enum class IntegrationMethod { rk4, dopri5, rosenbrock4, sdirk3 };

struct IntegrationMethodRow {
    IntegrationMethod kind;
    const char* name;         ///< `simulation.method: NAME`
    bool fixed_step;          ///< steps of the sample interval (or of `step`), no error control
    bool explicit_rk4;        ///< those steps are classical RK4's, limited by the model's fastest mode
    bool uses_jacobian;       ///< the model's state Jacobian at every step (a stiff method)
    const char* failure_hint; ///< appended to a diverged candidate's message ("" for none)
};

inline constexpr std::array<IntegrationMethodRow, 4> kIntegrationMethods{{
    {IntegrationMethod::rk4, "rk4", true, true, false,
     "; a stiff candidate (a large stiffness or damping on a small inertia) needs a smaller simulation.step, or "
     "method: sdirk3"},
    {IntegrationMethod::dopri5, "dopri5", false, false, false, "; for a stiff candidate try method: sdirk3"},
    {IntegrationMethod::rosenbrock4, "rosenbrock4", false, false, true, ""},
    {IntegrationMethod::sdirk3, "sdirk3", true, false, true, ""},
}};

static_assert(rows_in_enumerator_order(kIntegrationMethods, static_cast<std::size_t>(IntegrationMethod::sdirk3) + 1),
              "every IntegrationMethod needs its row, in enumerator order");

constexpr const IntegrationMethodRow& integration_method_row(IntegrationMethod method) {  // rows[method]
    return kIntegrationMethods[static_cast<std::size_t>(method)];
}

/// Whether the method takes fixed steps on the sample grid (rk4, sdirk3).
constexpr bool takes_fixed_steps(IntegrationMethod method) { return integration_method_row(method).fixed_step; }

/// Whether those fixed steps are classical RK4's (rk4).
constexpr bool steps_by_rk4(IntegrationMethod method) { return integration_method_row(method).explicit_rk4; }

/// The row named `name`, or nullptr.
constexpr const IntegrationMethodRow* find_integration_method(std::string_view name) {
    return find_row_named(kIntegrationMethods, name);
}

}  // namespace tvid

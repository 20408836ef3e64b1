#pragma once
// The one switch from a state size known at run time to the fixed sizes the fixed-step
// RK4 over a state on the stack is compiled for (march_fixed_rk4, march_batch_rk4, the
// warm-up shooting's tangents, the PackedDual sensitivities).

#include <cstddef>
#include <type_traits>

namespace tvid {

/// The largest state marched over a fixed-size state (engine block with 4 cylinders:
/// 6 nodes, 12 states).
inline constexpr std::size_t kMaxFixedState = 16;

/// Whether a state of n values has a compiled fixed size: angles and speeds of 1 to
/// kMaxFixedState / 2 nodes.
constexpr bool has_fixed_state_size(std::size_t n) { return n >= 2 && n <= kMaxFixedState && n % 2 == 0; }

/// f(std::integral_constant<std::size_t, n>{}) when n has a compiled fixed size, else
/// otherwise(); both return the same type.
template <class F, class Otherwise>
auto dispatch_state_size(std::size_t n, F&& f, Otherwise&& otherwise) {
    static_assert(kMaxFixedState == 16, "one case per even size up to kMaxFixedState");
    switch (n) {
        case 2: return f(std::integral_constant<std::size_t, 2>{});
        case 4: return f(std::integral_constant<std::size_t, 4>{});
        case 6: return f(std::integral_constant<std::size_t, 6>{});
        case 8: return f(std::integral_constant<std::size_t, 8>{});
        case 10: return f(std::integral_constant<std::size_t, 10>{});
        case 12: return f(std::integral_constant<std::size_t, 12>{});
        case 14: return f(std::integral_constant<std::size_t, 14>{});
        case 16: return f(std::integral_constant<std::size_t, 16>{});
        default: return otherwise();
    }
}

}  // namespace tvid

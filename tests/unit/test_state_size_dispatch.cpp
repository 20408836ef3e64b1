// The switch from a run-time state size to the compiled fixed sizes
// (lib/tvid/sim/state_size_dispatch.hpp).
#include <catch2/catch.hpp>

#include <cstddef>
#include <type_traits>

#include "tvid/sim/state_size_dispatch.hpp"

namespace TVID_UNITY_ID {  // unique to this file in a unity build (tests/CMakeLists.txt)

using namespace tvid;

TEST_CASE("dispatch_state_size calls the fixed size for every even size up to the largest, else the fallback",
          "[simulate]") {
    const auto fixed = []<std::size_t N>(std::integral_constant<std::size_t, N>) { return static_cast<int>(N); };
    const auto otherwise = [] { return -1; };
    for (std::size_t n = 0; n <= kMaxFixedState + 3; ++n) {
        const bool compiled = n >= 2 && n <= kMaxFixedState && n % 2 == 0;
        CHECK(has_fixed_state_size(n) == compiled);
        CHECK(dispatch_state_size(n, fixed, otherwise) == (compiled ? static_cast<int>(n) : -1));
    }
}

}  // namespace TVID_UNITY_ID

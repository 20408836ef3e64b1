#pragma once
// Options of a multistart least-squares fit (multistart.hpp): Levenberg–Marquardt from N
// Latin-hypercube points of the initial search box.

#include <cstdint>
#include <optional>

namespace tvid {

struct MultistartSettings {
    int starts = 8;            ///< Latin-hypercube starts in the range box
    std::uint64_t seed = 1;    ///< seed of the Latin-hypercube sample
    /// Trial steps of each start's Levenberg–Marquardt; none: those of `lm.max_iterations`.
    std::optional<int> max_iterations;
};

}  // namespace tvid

#pragma once
// Options of a multistart least-squares fit (multistart.hpp): Levenberg–Marquardt from N
// Latin-hypercube points of the initial search box, raced against each other.

#include "tvid/optim/settings_problem.hpp"
#include <cstdint>
#include <optional>

namespace tvid {

struct MultistartSettings {
    int starts = 8;            ///< Latin-hypercube starts in the range box
    std::uint64_t seed = 1;    ///< seed of the Latin-hypercube sample
    /// Trial steps of each start's Levenberg–Marquardt; none: those of `lm.max_iterations`.
    std::optional<int> max_iterations;
    /// Points drawn for one start at most. A drawn point whose simulation fails at the start
    /// (a candidate the integrator cannot simulate) is replaced by another, drawn uniformly
    /// in the range box from a stream of its own (the seed, the start, the draw), so that
    /// the starts asked for are run; a start whose every draw fails is reported as failed.
    int max_draws = 10;
    /// Race the starts (multistart_race.hpp): at `race_iterations` trial steps, and at
    /// twice, four times as many, the worse half of the starts still running stop.
    bool race = true;
    int race_iterations = 4;
};

/// The first problem of the settings, or none.
std::optional<SettingsProblem> validate(const MultistartSettings& settings);

}  // namespace tvid

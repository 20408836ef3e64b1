#pragma once
// The initial-state kinds, one row each, as elements, optimizers and integration methods
// have theirs: the name `initial_state:` gives, the keys of its own that the detailed form
// `initial_state: { kind: NAME, … }` takes, and the traits that the loader's checks, the
// start's sensitivity and the reports read. How each kind starts a window is in
// estimation/window_start.cpp (WindowStarts::start) and its sensitivity in
// estimation/forward_sensitivity.cpp (start_sensitivity): one case each, which the compiler
// checks for every enumerator (-Wswitch). `estimated` is not a kind of its own: it
// identifies the start of a kind (its `from:`), experiment/estimated_start.hpp.
//
// Adding a kind: its enumerator and row here, its case in WindowStarts::start and in
// ForwardSensitivity::start_sensitivity, and its reader in read_initial_state when it has keys.

#include <array>
#include <cstddef>
#include <string_view>

#include "tvid/util/kind_table.hpp"

namespace tvid {

enum class InitialStateKind { equilibrium, rest, measured, steady };

struct InitialStateRow {
    InitialStateKind kind;
    const char* name;            ///< `initial_state: NAME` or `{ kind: NAME, … }`
    /// Its own keys beside `kind` (steady: node, speed, samples), read by its reader; a
    /// kind with none takes the short form too.
    std::array<const char*, 3> keys;
    /// A turning line (an engine's cylinders, read by crank angle) may start so.
    bool turns;
    /// The start is a static balance (every speed zero, the stiffnesses carrying the
    /// inputs): no speed source may turn a node, and no controller integral may hold one.
    bool static_balance;
    /// The start reads a measured speed among the outputs (and, with a crank-angle channel,
    /// the measured angle through a warm-up shooting).
    bool reads_measured_speed;
    const char* summary;         ///< for messages and docs
};

inline constexpr std::array<InitialStateRow, 4> kInitialStateKinds{{
    {InitialStateKind::equilibrium, "equilibrium", {}, false, true, false,
     "the static equilibrium under the inputs at the window's start (Yoshida & Takamatsu eq. 18)"},
    {InitialStateKind::rest, "rest", {}, false, false, false, "every angle and speed zero"},
    {InitialStateKind::measured, "measured", {}, true, false, true,
     "every node at the first measured speed through the gear ratios (and the measured crank angle)"},
    {InitialStateKind::steady, "steady", {"node", "speed", "samples"}, true, false, false,
     "the line in steady rotation at a node's speed, twisted to carry the mean inputs"},
}};

static_assert(rows_in_enumerator_order(kInitialStateKinds, static_cast<std::size_t>(InitialStateKind::steady) + 1),
              "every InitialStateKind needs its row, in enumerator order");

constexpr const InitialStateRow& initial_state_row(InitialStateKind kind) {
    return kInitialStateKinds[static_cast<std::size_t>(kind)];
}

/// The row named `name`, or nullptr.
constexpr const InitialStateRow* find_initial_state(std::string_view name) {
    return find_row_named(kInitialStateKinds, name);
}

}  // namespace tvid

#pragma once
// What every optimizer kind's reader of its settings section shares: integers as int, seeds,
// and the settings' one check (optim/settings_validation.hpp, after Ceres'
// Solver::Options::IsValid) turned into "FILE:LINE: estimation.<section>.<key>: <message>".
// Written over the map type (experiment/yaml_reader.hpp's YamlMap), so that the kinds'
// headers need no YAML.

#include <algorithm>
#include <climits>
#include <cstdint>
#include <optional>

#include "tvid/optim/settings_validation.hpp"

namespace tvid::settings_reading {

/// An integer setting as an int. Out-of-range values stay out of range (saturated), so the
/// settings' validation reports them.
template <class Map>
int integer(const Map& m, const char* key) {
    return static_cast<int>(std::clamp<long long>(m.integer(key), INT_MIN, INT_MAX));
}

/// A seed: any integer that is not negative.
template <class Map>
std::uint64_t seed(const Map& m) {
    const long long seed = m.integer("seed");
    if (seed < 0) m.fail("seed", "the seed must not be negative");
    return static_cast<std::uint64_t>(seed);
}

/// Fails on the settings' first problem, if any.
template <class Map>
void fail_on_problem(const Map& m, const std::optional<SettingsProblem>& problem) {
    if (!problem) return;
    if (problem->missing) m.fail_missing(problem->key, problem->message);
    m.fail(problem->key, problem->message);
}

}  // namespace tvid::settings_reading

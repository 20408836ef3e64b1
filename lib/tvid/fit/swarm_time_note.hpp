#pragma once
// The swarm's running time foretold from its first iteration, said before the rest runs:
// the paper's swarm (512 particles, 250 iterations, the default optimizer) takes hours on a
// long recording where Levenberg–Marquardt takes seconds.

#include <cmath>
#include <cstdio>
#include <string>

#include "tvid/experiment/experiment.hpp"
#include "tvid/experiment/optimizer_kinds.hpp"

namespace tvid {

/// A swarm whose whole run is foretold to take at least this long is announced.
constexpr double kSwarmNoteSeconds = 60.0;

/// Seconds, roughly: "0.8 s", "51 s", "12 min", "3.5 h", "763 h".
inline std::string rough_duration_text(double seconds) {
    char buf[48];
    if (seconds < 10) std::snprintf(buf, sizeof buf, "%.2g s", seconds);
    else if (seconds < 100) std::snprintf(buf, sizeof buf, "%.0f s", seconds);
    else if (seconds < 6000) std::snprintf(buf, sizeof buf, "%.0f min", seconds / 60);
    else if (seconds < 36000) std::snprintf(buf, sizeof buf, "%.1f h", seconds / 3600);
    else std::snprintf(buf, sizeof buf, "%.0f h", seconds / 3600);
    return buf;
}

/// What `tvid fit` says after the swarm's first iteration, which scored its `particles`
/// initial particles in `first_seconds`: how long its iterations will take at most (each
/// scores only the particles that moved, each stopped once its cost passes its own best, so
/// they seldom take longer than the first). With no optimizer given, the swarm is the default,
/// and the line names the local alternative. "" when the optimizer runs no swarm, the swarm
/// has no iterations after the first, or the whole run is foretold under kSwarmNoteSeconds.
inline std::string swarm_time_note(const EstimationSettings& settings, std::size_t free_parameters,
                                   long long particles, double first_seconds) {
    const int iterations = settings.pso.iterations;
    if (!optimizer_traits(settings.optimizer).swarm || iterations < 1 || !std::isfinite(first_seconds)) return "";
    const double rest = first_seconds * iterations;
    if (first_seconds + rest < kSwarmNoteSeconds) return "";
    std::string text = std::string(optimizer_name(settings.optimizer)) + ": scoring the " + std::to_string(particles) +
                       " initial particles took " + rough_duration_text(first_seconds) + "; " +
                       std::to_string(iterations) + " iterations more will take at most about " +
                       rough_duration_text(rest);
    if (settings.optimizer == OptimizerKind::pso_lm) text += ", then LM polishes the best particle";
    if (!settings.optimizer_given) {
        const std::string m = std::to_string(free_parameters);
        text += std::string(" (the swarm is the default, as the experiment names no optimizer: `optimizer: lm`") +
                (settings.cost == CostKind::l2 ? "" : " with `cost: l2`") +
                " fits locally from the init values, each step one simulation with " +
                (settings.jacobian == JacobianKind::fd ? "2 × " + m + " more for its differences)"
                                                       : "its " + m + " sensitivities)");
    }
    return text;
}

}  // namespace tvid

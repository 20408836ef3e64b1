#pragma once
// The `windows:` section: estimation and validation windows of the recording, given as
// `time: [a, b]` (seconds), `samples: [a, b]` (0-based data rows), `cycle: k` or
// `cycles: [a, b]` (engine cycles of the crank-angle channel, numbered from 0 = the first
// complete cycle), resolved to sample indices, with an optional warm-up (`warmup: 0.05`
// seconds or `warmup: { cycles: 1 }`) simulated before each window and not scored.

#include <vector>

#include "tvid/experiment/yaml_reader.hpp"

namespace tvid {

struct WindowSet {
    std::vector<Window> estimation;
    std::vector<Window> validation;
    double warmup = 0.0;     ///< seconds
    int warmup_cycles = 0;
};

/// The recording's clocks: time [s] (strictly increasing) and, when the experiment has
/// `data.angle`, the cumulative crank angle [deg] (strictly increasing) and the cycle length.
struct RecordingAxes {
    const std::vector<double>& time;
    std::vector<double> crank_deg;  ///< empty without data.angle
    double cycle_deg = 720.0;
};

WindowSet read_windows(const YamlMap& windows, const RecordingAxes& axes);

}  // namespace tvid

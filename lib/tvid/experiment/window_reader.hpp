#pragma once
// The `windows:` section: estimation and validation windows of the recording, given as
// `time: [a, b]` (seconds), `samples: [a, b]` (0-based data rows), `cycle: k` or
// `cycles: [a, b]` (engine cycles of the crank-angle channel, numbered from 0 = the first
// complete cycle), resolved to sample indices, with an optional warm-up (`warmup: 0.05`
// seconds or `warmup: { cycles: 1 }`) simulated before each window and not scored. With
// several recordings (data.recordings) each window names its recording (`recording: NAME`)
// and is resolved on that recording's own clock and crank angle; a window that names only
// its recording covers all of it.

#include <string>
#include <vector>

#include "tvid/experiment/yaml_reader.hpp"

namespace tvid {

struct WindowSet {
    std::vector<Window> estimation;
    std::vector<Window> validation;
    double warmup = 0.0;     ///< seconds
    int warmup_cycles = 0;
};

/// A recording's clocks: time [s] (strictly increasing) and, when the experiment has
/// `data.angle`, the cumulative crank angle [deg] (strictly increasing) and the cycle length.
struct RecordingAxes {
    const std::vector<double>& time;
    std::vector<double> crank_deg;  ///< empty without data.angle
    double cycle_deg = 720.0;
    std::string name;               ///< data.recordings[k].name; empty for data.file
    std::size_t first_row = 0;      ///< its first row in the table the recordings are joined in
};

/// One RecordingAxes per recording, in order. The windows' samples are rows of the joined
/// table, and each window's label starts with its recording's name when it has one.
WindowSet read_windows(const YamlMap& windows, const std::vector<RecordingAxes>& recordings);

}  // namespace tvid

#pragma once
// The `windows:` section: estimation and validation windows of the recording, given as
// `time: [a, b]` (seconds) or `samples: [a, b]` (0-based data rows), resolved to
// sample indices, with an optional warm-up simulated before each window and not scored.

#include <vector>

#include "tvid/experiment/yaml_reader.hpp"

namespace tvid {

struct WindowSet {
    std::vector<Window> estimation;
    std::vector<Window> validation;
    double warmup = 0.0;  ///< seconds
};

/// `time` is the recording's time column (strictly increasing).
WindowSet read_windows(const YamlMap& windows, const std::vector<double>& time);

}  // namespace tvid

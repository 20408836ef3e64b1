#pragma once
// The experiment that a candidate input would make: the loaded experiment's model,
// parameters, start and simulation settings, played with the candidate as the designed
// input and every other time input held at its design level, over one window from the
// first sample. Its measured outputs are zero: only the sensitivities of the simulated
// outputs are used (design/predicted_uncertainty.hpp).

#include <vector>

#include "tvid/design/design_spec.hpp"
#include "tvid/experiment/experiment.hpp"

namespace tvid {

/// `time` strictly increasing, `input` the designed input's samples in its channel's unit.
/// A steady start read from a column takes the level of the time input bound to that column
/// (the design's base for the designed input), or else the column's mean over the loaded
/// experiment's first estimation window.
Experiment design_experiment(const Experiment& ex, const DesignSpec& spec, const std::vector<double>& time,
                             const std::vector<double>& input);

}  // namespace tvid

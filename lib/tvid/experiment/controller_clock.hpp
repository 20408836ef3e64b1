#pragma once
// A sampled controller's clock against the recordings: it samples at the multiples of its
// sample_period, and every simulation stops only at the recording's samples, so those
// instants must be samples; and a warm-up shot on the crank angle marches apart from its
// window, which a controller's memory cannot follow.

#include "tvid/experiment/data_reader.hpp"
#include "tvid/experiment/experiment.hpp"
#include "tvid/experiment/yaml_reader.hpp"

namespace tvid {

/// For each entry of model.elements with a sample_period: refuses (naming the entry's key)
/// a period that is not a whole number of a recording's sample intervals (within 1e-3 of
/// one: a logger's clock jitters), and a recording none of whose samples falls on its
/// clock; sets the controller's clock_tolerance in `network` to 1e-3 of the recordings'
/// sample interval.
void check_controller_clocks(const YamlMap& model, const DataSection& recorded, NetworkSpec& network);

/// The shortest time that every sampled controller's period divides (their common
/// multiple), 0 without one: a recording laid after another is moved by a multiple of it,
/// so that each controller samples at multiples of its period on the recording's own clock.
double common_controller_period(const NetworkSpec& network);

/// Refuses (at initial_state) a sampled controller with a crank-angle warm-up, whose
/// shooting marches the warm-up apart from the window: the controller's memory restarts
/// with each march.
void refuse_sampled_warmup(const YamlMap& top, const Experiment& ex);

}  // namespace tvid

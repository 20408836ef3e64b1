#pragma once
// A sampled controller's clock against the recordings: it samples at the multiples of its
// sample_period, and every simulation stops only at the recording's samples, so those
// instants must be samples.

#include "tvid/experiment/data_reader.hpp"
#include "tvid/experiment/yaml_reader.hpp"

namespace tvid {

/// For each entry of model.elements with a sample_period: refuses (naming the entry's key)
/// a period that is not a whole number of a recording's sample intervals, a recording none
/// of whose samples falls on its clock, and a crank-angle channel (whose warm-up shooting
/// restarts the simulation where a controller's memory cannot follow).
void check_controller_clocks(const YamlMap& model, const DataSection& recorded);

}  // namespace tvid

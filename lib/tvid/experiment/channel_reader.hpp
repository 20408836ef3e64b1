#pragma once
// The `inputs:` and `outputs:` sections: which CSV column feeds each model input and
// which column each model output is compared with, with an optional unit conversion
// (`unit: bar`, `unit: rpm`, or `scale: 1e5`) to SI.

#include <vector>

#include "tvid/experiment/data_reader.hpp"
#include "tvid/experiment/yaml_reader.hpp"
#include "tvid/model/network_spec.hpp"

namespace tvid {

/// One binding per network input, in network order; every input must be bound.
/// `declared`: the names under `parameters:`. A channel's `delay:` may name one; it is
/// recorded in network.delay_parameters (and added to a preset's parameter names). Every
/// recording must hold each channel's column, and be longer than its delay.
std::vector<ChannelBinding> read_inputs(const YamlMap& inputs, NetworkSpec& network,
                                        const std::vector<RecordingRead>& recordings,
                                        const std::vector<std::string>& declared);

struct OutputBindings {
    std::vector<ChannelBinding> channels;
    std::vector<int> indices;  ///< into NetworkSpec::outputs, per channel
};

/// For a preset the keys are the preset's outputs; for a custom network each entry
/// defines an output (`speed: NODE`, `angle: NODE` or `torque: ELEMENT`, optional
/// `offset`) and is appended to `network.outputs`.
OutputBindings read_outputs(const YamlMap& outputs, NetworkSpec& network, const std::vector<RecordingRead>& recordings,
                            const std::vector<std::string>& declared);

/// Refuses a cylinder pressure channel (an input read by crank angle) whose values, in Pa
/// after the unit conversion, cannot be an absolute cylinder pressure: negative, a peak
/// below 0.8 bar or above 500 bar, or never below 5 bar (the gas exchange strokes are near
/// atmospheric). This catches a unit off by a factor of 100 or more (bar read as Pa, kPa
/// as bar, ...); the message names the units the numbers fit. Each recording is checked.
void check_cylinder_pressures(const YamlMap& inputs, const std::vector<ChannelBinding>& bindings,
                              const std::vector<RecordingRead>& recordings);

/// The factor that converts a value in `unit` to SI; 0 for an unknown unit.
double unit_to_si(const std::string& unit);

}  // namespace tvid

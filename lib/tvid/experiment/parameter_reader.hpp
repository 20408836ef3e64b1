#pragma once
// The `parameters:` section: for every model parameter its start value and bounds and
// initial search range when free, or its value when fixed.
//
//   rho1:  { init: 1.5, min: 0.1, max: 10, range: [1, 2] }   # free
//   sigma: { value: 1132.81, fixed: true }                   # fixed (`value:` alone also fixes)

#include <cstddef>
#include <string>
#include <vector>

#include "tvid/experiment/yaml_reader.hpp"
#include "tvid/model/network_spec.hpp"

namespace tvid {

/// One setting per network parameter, in network order. Every network parameter must be
/// declared and every declared one must be a network parameter; `needs_search_box`: each
/// free parameter needs a `range` or both bounds (the particle swarm starts in that box).
/// A value, bound or range that makes the model unphysical is refused: inertias, σ and
/// cylinder dimensions must be positive; stiffness, damping, friction, backlash and
/// reciprocating mass cannot be negative.
/// A parameter `{ expr: "FORMULA" }` is a formula of others (model/parameter_formula.hpp):
/// held, its value the formula's at every evaluation; `network` gets the formulas in the
/// order they resolve, and a cycle among them is refused naming it.
std::vector<ParameterSetting> read_parameters(const YamlMap& parameters, NetworkSpec& network,
                                              bool needs_search_box);

/// Why `value` cannot be parameter `index` of `network` with the setting `setting`: a
/// sign its physics forbids ("must be positive: J1 is an inertia, got -1"), or outside
/// the bounds of a free parameter; "" when it can. For parameter files given to
/// simulate, validate and sensitivity.
std::string parameter_value_problem(const NetworkSpec& network, const ParameterSetting& setting, std::size_t index,
                                    double value);

}  // namespace tvid

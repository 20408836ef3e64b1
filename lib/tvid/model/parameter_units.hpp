#pragma once
// The SI unit of each model parameter and output, as `tvid models` lists them for a
// preset, and from the field each parameter fills for a custom network (a spring's k is a
// stiffness in N m/rad, a node's J an inertia in kg m^2, …). Reports write them next to the
// values.

#include <cstddef>
#include <string>
#include <vector>

#include "tvid/model/network_spec.hpp"

namespace tvid {

/// One per NetworkSpec::parameter_names; "" for a parameter that fills no known field. A
/// field of an element on a linear node (NodeSpec::linear) and a linear node's mass take
/// their translational units (N/m, N s/m, N, m, kg).
std::vector<std::string> parameter_units(const NetworkSpec& network);

/// The output's unit, from its kind's row (model/output_kinds.hpp): "rad/s", "rad" or
/// "N m", or on a linear node "m/s", "m" or "N".
std::string output_unit(const NetworkSpec& network, const OutputSpec& output);

/// The unit of the network's input by time `input` (NetworkSpec::input_names), from the
/// kind of the element that reads it (a torque's "N m", a speed source's "rad/s"; on a
/// linear node "N", "m/s"); "" if no element reads it.
std::string input_unit(const NetworkSpec& network, std::size_t input);

/// The node of the element that reads the network's input by time `input`, whose motion
/// (rotational or linear) gives the input's unit; -1 if no element reads it.
int input_node(const NetworkSpec& network, std::size_t input);

/// A rotational SI unit as its translational analogue reads it: N m → N, rad → m,
/// kg m^2 → kg (N m/rad → N/m, N m s/rad → N s/m, rad/s → m/s, …); other units unchanged.
std::string translational_unit(const std::string& rotational);

}  // namespace tvid

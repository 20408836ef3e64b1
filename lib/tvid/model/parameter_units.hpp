#pragma once
// The SI unit of each model parameter and output, as `tvid models` lists them for a
// preset, and from the field each parameter fills for a custom network (a spring's k is a
// stiffness in N m/rad, a node's J an inertia in kg m^2, …). Reports write them next to the
// values.

#include <string>
#include <vector>

#include "tvid/model/network_spec.hpp"

namespace tvid {

/// One per NetworkSpec::parameter_names; "" for a parameter that fills no known field.
std::vector<std::string> parameter_units(const NetworkSpec& network);

/// "rad/s", "rad" or "N m".
const char* output_unit(const OutputSpec& output);

}  // namespace tvid

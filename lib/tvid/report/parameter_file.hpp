#pragma once
// Reading a parameter set back (`tvid simulate|validate --params P.json`): a params.json
// written by `tvid fit`, or a plain JSON object {"name": value, ...}.

#include <filesystem>
#include <vector>

#include "tvid/experiment/experiment.hpp"

namespace tvid {

/// The full model parameter vector: the experiment's init/fixed values, overwritten by
/// every parameter the file names. Throws InputError for an unreadable file, bad JSON,
/// a non-numeric value or a name that is not a model parameter.
std::vector<double> read_parameter_file(const std::filesystem::path& file, const Experiment& experiment);

/// The experiment's own values (init for free parameters, value for fixed ones).
std::vector<double> initial_parameters(const Experiment& experiment);

}  // namespace tvid

#pragma once
// Reading a parameter set back (`tvid simulate|validate --params P.json`): a params.json
// written by `tvid fit`, or a plain JSON object {"name": value, ...}.

#include <filesystem>
#include <string>
#include <vector>

#include "tvid/experiment/experiment.hpp"

namespace tvid {

/// The full model parameter vector: the experiment's init/fixed values, overwritten by
/// every parameter the file names. Throws InputError for an unreadable file, bad JSON,
/// a non-numeric value or a name that is not a model parameter.
///
/// A params.json's `initial_states` (an estimated start): with `seeds` (this experiment's
/// ProblemDefinition::EstimatedStarts::seed), each start is taken as stored, its `value`,
/// whatever this experiment's seed is now (its init values may have moved the recipe's
/// state): the correction read is value − seed. An entry for another window than this
/// experiment estimates under that parameter, or for a coordinate it does not estimate,
/// is left out and said in `notes` (that window then starts from its recipe).
std::vector<double> read_parameter_file(const std::filesystem::path& file, const Experiment& experiment,
                                        const std::vector<std::vector<double>>* seeds = nullptr,
                                        std::vector<std::string>* notes = nullptr);

/// The experiment's own values (init for free parameters, value for fixed ones).
std::vector<double> initial_parameters(const Experiment& experiment);

}  // namespace tvid

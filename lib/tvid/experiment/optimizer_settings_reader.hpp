#pragma once
// The optimizer choice and the settings of the general optimizers under `estimation:`:
//
//   optimizer: nlopt        # pso | lm | nlopt | pso+lm | multistart
//   nlopt: { algorithm: LN_BOBYQA, local_algorithm: LN_SBPLX, max_evaluations: 5000,
//            max_seconds: 600, xtol_rel: 1e-8, ftol_rel: 1e-12, population: 0, seed: 1 }
//   multistart: { starts: 8, seed: 1, max_iterations: 100 }
//
// and the checks that need the parameters too (a global NLopt algorithm searches within
// the bounds; multistart samples the range box).

#include <vector>

#include "tvid/experiment/yaml_reader.hpp"

namespace tvid {

/// `optimizer:`, one of the five names; otherwise an error listing them.
OptimizerKind read_optimizer_kind(const YamlMap& estimation);

/// `nlopt:`. An algorithm name NLopt does not know is an error listing the valid ones.
NloptSettings read_nlopt(const YamlMap& m);

/// `multistart:`.
MultistartSettings read_multistart(const YamlMap& m);

/// Fails at the first free parameter the optimizer cannot work with: without both bounds
/// for a global NLopt algorithm, without a range or both bounds for multistart.
void check_search_box(const YamlMap& parameters, const std::vector<ParameterSetting>& settings,
                      const EstimationSettings& estimation);

}  // namespace tvid

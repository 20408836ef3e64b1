#pragma once
// The optimizer choice and the optimizers' settings sections under `estimation:`:
//
//   optimizer: nlopt        # pso | lm | nlopt | pso+lm | multistart
//   pso: { start: grid, grid: 2, iterations: 250, w: 1, c1: 0.4, c2: 0.4, seed: 1, ... }
//   lm: { max_iterations: 200, ftol: 1e-10, xtol: 1e-10, gtol: 1e-10, stol: 0.1, jacobian: sensitivity }
//   nlopt: { algorithm: LN_BOBYQA, local_algorithm: LN_SBPLX, max_evaluations: 5000,
//            max_seconds: 600, xtol_rel: 1e-8, ftol_rel: 1e-12, population: 0, seed: 1 }
//   multistart: { starts: 8, seed: 1, max_iterations: 100, max_draws: 10, race: true, race_iterations: 4 }
//
// Each section is read by its kind (experiment/optimizer_kinds/NAME.hpp: its keys, its
// reader, which validates the settings in one call). Then the checks that need the
// parameters too (a global NLopt algorithm searches within the bounds; multistart samples
// the range box).

#include <string>
#include <vector>

#include "tvid/experiment/yaml_reader.hpp"

namespace tvid {

/// `optimizer:`, one of the kinds' names; otherwise an error listing them.
OptimizerKind read_optimizer_kind(const YamlMap& estimation);

/// The keys of the optimizers' settings sections (`pso`, `lm`, ...).
std::vector<std::string> optimizer_section_keys();

/// Every settings section `estimation` gives, each read by its kind into `settings`.
void read_optimizer_sections(const YamlMap& estimation, EstimationSettings& settings);

/// Fails at the first free parameter the optimizer cannot work with: without both bounds
/// for a global NLopt algorithm, without a range or both bounds for multistart.
void check_search_box(const YamlMap& parameters, const std::vector<ParameterSetting>& settings,
                      const EstimationSettings& estimation);

}  // namespace tvid

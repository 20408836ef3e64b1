#pragma once
// A design that does not rely on knowing the answer: the criterion averaged over the
// nominal parameters and a few draws about them (design.robust), each free parameter
// multiplied by a factor drawn log-uniformly within [1/(1 + spread), 1 + spread] and held
// within its bounds. The draws come from the seed alone: the same on every machine and
// thread count.

#include <vector>

#include "tvid/design/design_spec.hpp"
#include "tvid/design/predicted_uncertainty.hpp"
#include "tvid/experiment/experiment.hpp"

namespace tvid {

/// The nominal parameter vector first, then spec.draws drawn ones (full vectors, the
/// experiment's order; fixed and formula parameters as nominal).
std::vector<std::vector<double>> design_parameter_sets(const Experiment& ex, const DesignSpec& spec,
                                                       const std::vector<double>& nominal);

/// exp of the mean log of the criterion over the sets' predictions (the geometric mean);
/// infinite when one of them did not simulate or left a parameter undetermined.
double averaged_criterion(const std::vector<PredictedUncertainty>& predictions, DesignCriterion c);

}  // namespace tvid

#pragma once
// What the data determine among parameters they cannot pin one by one: weakly determined
// parameters whose estimates are strongly correlated (|ρ| above a threshold, linked in
// chains) form a group, and the group's best-determined combination is the eigenvector of
// their relative covariance (p_j's variance over p_j²) with the smallest eigenvalue. On one
// engine cycle the dampings of the throws and the wheels trade against each other; their
// weighted sum, the total drag the speed trace shows, is well determined.

#include <cstddef>
#include <vector>

#include "tvid/analysis/identifiability.hpp"
#include "tvid/analysis/uncertainty.hpp"

namespace tvid {

struct DeterminedCombination {
    std::vector<std::size_t> members;  ///< free-parameter indices, in order
    /// Σ weights[k]·p_members[k], the weights in the parameters' own units scaled so that the
    /// largest |weight| is 1.
    std::vector<double> weights;
    double value = 0.0;                ///< of the combination at the estimate
    double std_error = 0.0;            ///< √(wᵀ Σ w)
    double smallest_member_error = 0.0, largest_member_error = 0.0;  ///< the members' relative standard errors
    double weakest_correlation = 0.0;  ///< the smallest |ρ| of a link that joined the group
};

/// The groups of at least two weakly determined parameters (IdentifiabilityFlag::weak, a
/// finite standard error, a value other than 0) linked by |ρ| ≥ `correlated`, each with its
/// best-determined combination. Empty when the covariance is not available.
std::vector<DeterminedCombination> determined_combinations(const ParameterUncertainty& uncertainty,
                                                           const IdentifiabilityReport& identifiability,
                                                           const std::vector<double>& values, double correlated = 0.9);

}  // namespace tvid

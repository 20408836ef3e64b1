#pragma once
// The cost of several candidates of an IdentificationProblem at once: their simulations
// run side by side in the lanes of packs (tvid/simd/pack.hpp), so that the element code
// works on kBatchLanes particles per instruction. Each lane's cost is the one
// IdentificationProblem::cost computes for its candidate, bit for bit: the same starts
// (the scalar start of each lane: equilibrium or warm-up shooting), the same RK4
// arithmetic, the same sums in the same order, the same stop at the bound.
//
// Used for fixed-step RK4 over a small state (every preset); other integrators adapt
// their steps to each candidate and run one candidate at a time.

#include <cstddef>
#include <memory>
#include <vector>

#include "tvid/estimation/identification_problem.hpp"
#include "tvid/model/network_model.hpp"
#include "tvid/simd/pack.hpp"

namespace tvid {

/// Candidates per batch: 8 doubles, two AVX2 registers worked on side by side.
inline constexpr int kBatchLanes = 16;
using BatchScalar = Pack<kBatchLanes>;

/// Per-thread scratch space of batch_costs, built once.
struct BatchWorkspace {
    explicit BatchWorkspace(const IdentificationProblem& problem);
    std::unique_ptr<ProblemWorkspace> scalar;  ///< each lane's start (equilibrium, warm-up shooting)
    NetworkModel<BatchScalar> model;
    std::vector<BatchScalar> params;           ///< full model parameter vector, lane by lane
    std::vector<double> u, u_stage;            ///< inputs at the sample and the RK4 stages
    std::size_t rhs_evaluations = 0;           ///< right-hand sides the scored lanes needed
};

/// Whether `problem`'s simulations can be batched: fixed-step RK4 over a state the
/// fixed-size RK4 takes (simulate_samples' own choice of that path).
bool batch_supported(const IdentificationProblem& problem);

/// costs[l] = problem.cost(candidates + l·dimension, ·, bounds[l]) for every l < count
/// (count <= kBatchLanes; bounds may be null: no bound). Never throws.
void batch_costs(const IdentificationProblem& problem, const double* candidates, std::size_t count,
                 const double* bounds, BatchWorkspace& ws, double* costs);

}  // namespace tvid

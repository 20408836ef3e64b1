#pragma once
// The cost of several candidates of an IdentificationProblem at once: their simulations
// run side by side in the lanes of packs (tvid/simd/pack.hpp), so that the element code
// works on kBatchLanes particles per instruction. Each lane's cost is the one
// IdentificationProblem::cost computes for its candidate, bit for bit: the same starts
// (the scalar start of each lane: equilibrium or warm-up shooting), the same RK4
// arithmetic, the same sums in the same order, the same stop at the bound. The groups are
// formed anew from the surviving candidates a few times a window, so that the stop at the
// bound saves the work of whole groups.
//
// Used for fixed-step RK4 over a small state (every preset); other integrators adapt
// their steps to each candidate and run one candidate at a time.

#include <array>
#include <atomic>
#include <cstddef>
#include <memory>
#include <span>
#include <vector>

#include "tvid/estimation/identification_problem.hpp"
#include "tvid/model/network_model.hpp"
#include "tvid/simd/pack.hpp"
#include "tvid/util/cache_line.hpp"

namespace tvid {

/// Candidates per group: 16 doubles, four AVX2 registers worked on side by side.
inline constexpr int kBatchLanes = 16;
using BatchScalar = Pack<kBatchLanes>;

/// Per-thread scratch space of batch_costs, built once; on cache lines of its own.
struct alignas(kCacheLine) BatchWorkspace {
    explicit BatchWorkspace(const IdentificationProblem& problem);
    std::unique_ptr<ProblemWorkspace> scalar;  ///< each lane's start (equilibrium, warm-up shooting)
    NetworkModel<BatchScalar> model;
    std::vector<BatchScalar> params;           ///< full model parameter vector, lane by lane
    std::vector<double> u, u_stage;            ///< inputs at the sample and the RK4 stages
    /// Per output whose delay is a parameter, per lane: the interval its reading found last
    /// (channel_delay.hpp), so that each lane reads its own shifted recording in O(1).
    std::vector<std::array<std::size_t, kBatchLanes>> delay_hints;
    std::size_t rhs_evaluations = 0;           ///< right-hand sides the scored lanes needed
    std::size_t pack_rhs_evaluations = 0;      ///< right-hand sides of packs (kBatchLanes lanes each)
};

/// Whether `problem`'s simulations can be batched: fixed-step RK4 over a state the
/// fixed-size RK4 takes (simulate_samples' own choice of that path), no filtered output,
/// and no input delayed by a parameter (the lanes share their inputs; an output's delay
/// parameter is read lane by lane).
bool batch_supported(const IdentificationProblem& problem);

/// Samples a window is marched at most before the groups are formed anew (and at least
/// kRegroupPieces pieces a window, if it is that long).
inline constexpr std::size_t kRegroupMinSamples = 64;
inline constexpr std::size_t kRegroupPieces = 16;

/// costs[i] = problem.cost(candidates + i·dimension, ·, bounds[i]) for every i < count
/// (bounds may be null: no bound), bit for bit, on one thread per workspace. The
/// candidates run in SIMD groups of kBatchLanes; each window is marched in up to
/// kRegroupPieces pieces, and before each piece the candidates still being scored (not
/// yet cut at their bound, not failed) are packed into groups anew, so that a group does
/// not keep running for one surviving lane while its others are done. Returns false when
/// `stop` (may be null) was set before every group was scored: the costs are then not
/// all computed (the skipped ones are +inf). Never throws.
bool batch_costs(const IdentificationProblem& problem, const double* candidates, std::size_t count,
                 const double* bounds, std::span<BatchWorkspace* const> workspaces, const std::atomic<bool>* stop,
                 double* costs);

/// The same on the calling thread with one workspace.
void batch_costs(const IdentificationProblem& problem, const double* candidates, std::size_t count,
                 const double* bounds, BatchWorkspace& ws, double* costs);

}  // namespace tvid

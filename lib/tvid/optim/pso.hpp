#pragma once
// Particle swarm optimization exactly as Yoshida & Takamatsu eq. 24:
//   p_i(k+1) = p_i(k) + v_i(k)
//   v_i(k+1) = η0 v_i(k) + η1 (P_i(k) − p_i(k)) + η2 (G(k) − p_i(k))
// with η0 ~ U[0,w], η1 ~ U[0,c1], η2 ~ U[0,c2], zero initial velocities and initial
// particles on the n^M grid of the initial search box (eq. 26), a Latin hypercube or
// uniform random sample. All random numbers are drawn serially from one seeded
// generator, and candidates are scored by a CandidateEvaluator, so the result is the
// same for the same seed whatever the number of threads.

#include <cstddef>
#include <functional>
#include <string>
#include <vector>

#include "tvid/optim/candidate_evaluator.hpp"
#include "tvid/optim/optimizer_summary.hpp"
#include "tvid/optim/pso_options.hpp"
#include "tvid/optim/termination.hpp"

namespace tvid {

/// Where the swarm may go (bounds; ±huge when unbounded) and where it starts (range box).
struct SearchBox {
    std::vector<double> lower, upper;
    std::vector<double> range_lower, range_upper;
};

/// How settled the swarm is when it stops. A swarm still spread over its box or still
/// improving has not converged: its best is not yet the optimum of the basin it is in, and
/// may not be in the optimum's basin at all.
struct PsoConvergence {
    /// Per searched parameter: the spread (max − min) of the particles' personal bests, over
    /// the box's width (in the searched scale: ln p for `scale: log`). 0: every particle
    /// remembers the same point.
    std::vector<double> spread;
    double max_spread = 0.0;          ///< the largest of them
    /// The global best's relative fall over the last `window` iterations,
    /// (J(k − window) − J(k)) / |J(k)|: 0 when it has stopped improving.
    double recent_improvement = 0.0;
    int window = 0;                   ///< max(10, iterations/10), at most the iterations run
};

/// The swarm's summary: best is the global best position G; iterations the swarm updates
/// done; evaluations the simulations run; failed_evaluations the candidates whose simulation
/// failed (cost +inf; a candidate whose partial cost had already reached its personal best
/// was stopped there, evaluate_bounded, and is not counted); history one row per iteration,
/// k = 0 … iterations; termination "iteration limit", "stopped" (the progress callback
/// returned false, or the evaluator was stopped mid-batch: that iteration is dropped) or
/// "all candidates failed"; success: the iterations ran out (the swarm's one stopping rule).
struct PsoSummary : OptimizerSummary {
    PsoSummary() { termination_type = TerminationType::iteration_limit; }
    int particles = 0;
    /// The first candidate whose simulation failed (empty when none did), for the report
    /// to say why (IdentificationProblem::failure).
    std::vector<double> first_failed;
    PsoConvergence convergence;      ///< at the last iteration
};

class ParameterScaling;
/// The summary of a swarm in search coordinates (parameter_scaling.hpp) as parameters: its
/// best point and its first failed candidate.
void to_parameters(const ParameterScaling& scaling, PsoSummary& summary);

/// Called after every iteration; return false to stop the swarm (e.g. on Ctrl-C).
using PsoProgress = std::function<bool(const HistoryRow&)>;

/// The initial particle positions (particle-major, M values each).
std::vector<double> pso_initial_positions(const PsoSettings& options, const SearchBox& box, std::size_t& count,
                                          std::uint64_t seed);

PsoSummary run_pso(const PsoSettings& options, const SearchBox& box, CandidateEvaluator& evaluator,
                   const PsoProgress& progress = {});

}  // namespace tvid

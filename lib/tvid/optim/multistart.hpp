#pragma once
// Multistart least squares: Levenberg–Marquardt from N points of a seeded Latin-hypercube
// sample of the range box, the lowest cost kept. A single LM run from a poor start can stop
// in a local minimum of a nonlinear model (the engine block from a corner of its box);
// spread starts reach the basin of the global one.
//
// The starts run in parallel, each on its own least-squares problem (one per start, from a
// factory) on a share of the threads. A start's result depends on its start point only, the
// best is the lowest cost (the lower start number on a tie), and the history is laid out in
// start order — so a seed gives the same result for any thread count.

#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "tvid/optim/levenberg_marquardt.hpp"
#include "tvid/optim/multistart_options.hpp"
#include "tvid/optim/pso.hpp"  // SearchBox, HistoryRow
#include "tvid/util/thread_budget.hpp"

namespace tvid {

struct StartResult {
    int start = 0;                   ///< 1-based
    std::vector<double> initial;     ///< the point its LM started from: the Latin-hypercube point, or its last redraw
    int draws = 1;                   ///< points drawn: 1 + the redraws of points that could not be simulated
    std::vector<double> best;        ///< where its LM stopped
    double initial_cost = 0.0;       ///< Σ r² at the start
    double best_cost = 0.0;          ///< Σ r² at `best` (+inf when the start failed)
    int iterations = 0;
    long long evaluations = 0;       ///< simulations (or residual + Jacobian calls when not counted)
    long long failed_evaluations = 0;
    long long right_hand_sides = 0;  ///< of the model, in its simulations (0 when not counted)
    std::string termination;         ///< LM's reason, or "not run" when the run was stopped before it
    TerminationType termination_type = TerminationType::not_run;
    bool success = false;            ///< an LM tolerance was met
    std::vector<HistoryRow> history; ///< its own LM history
};

/// Multistart's summary: best and best_cost the best start's; iterations the LM steps over
/// all starts; history the starts' histories one after the other in start order
/// (iterations numbered on, evaluations cumulative, best cost the lowest so far over the
/// starts before); termination "best of N starts: <best start's reason>", "stopped", …;
/// termination_type the best start's, or stopped, all_failed; success: the best start
/// converged.
struct MultistartSummary : OptimizerSummary {
    MultistartSummary() { termination_type = TerminationType::all_failed; }
    std::vector<StartResult> starts;  ///< in start order
    int best_start = 0;               ///< 1-based; 0 when every start failed
    long long right_hand_sides = 0;   ///< over every start
    int threads = 1;                  ///< starts run at once
    int threads_per_start = 1;        ///< each start's share while `threads` of them run
};

/// A fresh least-squares problem for one start, on its share of the multistart's cores:
/// each of its parallel regions takes share.team() threads, the cores over the starts
/// running at that moment (so the last starts of a race take up the cores the others left),
/// up to share.cores().
using LeastSquaresFactory = std::function<std::unique_ptr<LeastSquaresProblem>(const ThreadBudget& share)>;

/// Called (serialized) after every LM step of any start with running totals (iteration =
/// steps so far over all starts, evaluations so far, lowest cost so far); false stops every start.
using MultistartProgress = std::function<bool(const HistoryRow&)>;

/// The N start points (start-major, M values each) of the range box: a Latin hypercube.
std::vector<double> multistart_points(const MultistartSettings& settings, const SearchBox& box);

/// Draw `draw` (2, 3, …) of start `start` (1-based): a point drawn uniformly in the range box
/// from its own stream of (seed, start, draw), the same on any thread.
std::vector<double> multistart_redraw(const MultistartSettings& settings, const SearchBox& box, int start, int draw);

/// threads <= 0: all hardware threads. Throws std::invalid_argument when starts < 1.
MultistartSummary run_multistart(const MultistartSettings& settings, const LmSettings& lm, const SearchBox& box,
                                 int threads, const LeastSquaresFactory& make_problem,
                                 const MultistartProgress& progress = {});

class ParameterScaling;
/// The summary of a multistart in search coordinates (parameter_scaling.hpp) as parameters:
/// its best point, and each start's first and last point.
void to_parameters(const ParameterScaling& scaling, MultistartSummary& summary);

}  // namespace tvid

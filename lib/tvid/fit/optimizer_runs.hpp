#pragma once
// The general optimizers of a fit run on an IdentificationProblem: NLopt, the hybrid
// pso+lm, and multistart LM. Each fills its part of the FitResult and returns what every
// optimizer reports (run_fit in fit_run.cpp chooses among them).

#include "tvid/fit/fit_run.hpp"

namespace tvid {

/// Any NLopt algorithm from the experiment's init, on the configured cost (l1 or l2).
OptimizerRun run_nlopt_fit(const IdentificationProblem& problem, const FitOptions& options, FitResult& r);

/// The swarm on the l2 cost, then LM from its best particle.
OptimizerRun run_hybrid_fit(const IdentificationProblem& problem, const FitOptions& options, FitResult& r);

/// LM from Latin-hypercube starts of the range box, in parallel, the best kept.
OptimizerRun run_multistart_fit(const IdentificationProblem& problem, const FitOptions& options, FitResult& r);

}  // namespace tvid

#pragma once
// Why an optimizer stopped: a type that code decides on, next to the message that reports
// and the terminal show (after Ceres' Solver::Summary: termination_type and message).
// The messages are each optimizer's own ("cost change below ftol", "iteration limit",
// "best of 8 starts: step below xtol", ...); the types group them.

namespace tvid {

enum class TerminationType {
    converged,         ///< a tolerance was met (LM's ftol, xtol or gtol; NLopt's tolerances or stop value)
    iteration_limit,   ///< the iterations ran out (the swarm's only stopping rule; LM before a tolerance)
    evaluation_limit,  ///< NLopt's evaluation budget ran out
    time_limit,        ///< NLopt's time budget ran out
    no_progress,       ///< LM: rejected steps in a row, or stuck where the model fails; NLopt: roundoff limited
    start_failed,      ///< LM: the start could not be evaluated
    all_failed,        ///< every candidate, evaluation or start failed
    failed,            ///< NLopt gave up (failure, invalid arguments, out of memory)
    stopped,           ///< the progress callback said stop, or the problem was stopped mid-evaluation
    interrupted,       ///< a fit ended by a stop request (Ctrl-C): its best point so far
    not_run,           ///< a multistart start that a stop came before
    raced_out,         ///< a multistart start stopped by the race: its cost ranked in the worse half at a rung
};

}  // namespace tvid
